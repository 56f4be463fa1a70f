#pragma once
// The weather editor's document: the editable set of states of one folder (one JSON per state, id =
// file stem), with undo/redo, dirty tracking against what is on disk, safe saving and a watch on
// changes made by others. No UI, no GPU: the editor window draws it, the renderer gets its states.
//
//   WeatherDocument doc = WeatherDocument::open("content/weather", renderer_map_maker);
//   doc.set("storm", "coverage", 0.8, /*merge=*/true);      // slider drag: one undo step per drag
//   doc.begin_stroke("storm"); doc.paint("storm", MapChannel::Coverage, uv, 0.05f, 0.0f); doc.end_stroke();
//   for (const std::string& id : doc.take_changed())           // mirror into the live library
//     doc.has(id) ? library.put(doc.state(id)) : void(library.erase(id));
//   doc.save();                                                // all dirty states, or nothing
//
// Rules the implementation keeps:
// - An edit that throws (cumulo::Error naming the state, the parameter and the allowed range) changes
//   nothing. Every state held is one the loader accepts.
// - Undo steps hold whole states (JSON + painting pointer) before and after, so undo restores exactly.
// - Dirty = differs from the snapshot taken at open / the last save / the last reload, so undoing back
//   to the saved state is clean again.
// - A painting is an immutable PaintedCloudMap; each change makes a new one (the renderer compares
//   pointers). It stays in memory after a save (the same pixels as the PNG written), so undo/redo across
//   a save shows the right pixels even after the PNG is overwritten.
#include <filesystem>
#include <functional>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "editor/model/cloud_map_canvas.h"
#include "engine/core/json.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::editor {

// Renders a state's current cloud map (its PNG, or the procedural map) to RGBA8 pixels: the start of
// a painting. The editor passes the renderer's generator; tests a simple fake.
using MapMaker = std::function<PaintedCloudMap(const clouds::weather::CloudMapSource&)>;

// [A-Za-z0-9_-]+, at most 100 characters: a file stem on every platform.
bool valid_state_id(std::string_view id);

// The file a painting is saved as, beside its state: "<id>.cloud_map.png".
std::string painted_map_file_name(const std::string& id);

// A state's JSON as saved: 2-space indent, keys in the order of the shipped files ($schema first),
// unknown keys after them, a final newline.
std::string weather_state_text(const Json& state);

struct DiskEvent {
  enum class Kind {
    Reloaded,   // the file changed and the state was clean: the disk version is taken
    Conflict,   // changed (or deleted) on disk while edited here: mine is kept; see resolve_conflict
    Malformed,  // the file no longer loads: the last good state is kept; message says why
    Added,      // a new state file
    Removed,    // a clean state's file was deleted: the state is removed
  };
  Kind kind;
  std::string id;
  std::string message;  // for a person: names the file (and the JSON path for Malformed)
};
const char* disk_event_name(DiskEvent::Kind k);

class WeatherDocument {
 public:
  // Every `*.json` of the folder. A file that does not load is not fatal: it is listed in problems()
  // and skipped. Throws only for a folder that cannot be listed.
  static WeatherDocument open(const std::filesystem::path& folder, MapMaker make_map);

  const std::filesystem::path& folder() const { return folder_; }
  const std::vector<std::string>& problems() const { return problems_; }  // from open(), one per file
  std::vector<std::string> ids() const;                                   // sorted
  bool has(const std::string& id) const { return entries_.count(id) > 0; }
  std::filesystem::path file(const std::string& id) const { return folder_ / (id + ".json"); }
  const Json& json(const std::string& id) const;  // throws naming the unknown id
  // Validated; cloud_map.painted is set while the state has a painting in memory (unsaved, or saved
  // in this session: the same pixels as its PNG).
  clouds::weather::WeatherState state(const std::string& id) const;

  // ---- Edits: each is one undo step, and throws without changing anything when refused.
  // A known parameter (weather_params.h). merge: coalesce with the previous step when it was a merged
  // set of the same state and parameter (a slider drag); a drag back to the start value leaves no step.
  void set(const std::string& id, std::string_view param, const Json& value, bool merge = false);
  // A new state with the template's parameters but no painting, PNG or description; an empty template:
  // the loader's defaults (clear sky, light wind).
  void create(const std::string& new_id, const std::string& template_id = {});
  void duplicate(const std::string& src, const std::string& new_id);  // everything, painting included
  void rename(const std::string& from, const std::string& to);
  void remove(const std::string& id);

  // ---- Painting: a stroke is one undo step. It starts from the state's painting, else from
  // make_map(state.cloud_map). Another edit, undo or save ends an open stroke first.
  void begin_stroke(const std::string& id);
  PaintRect paint(const std::string& id, MapChannel channel, glm::vec2 uv, float radius, float value,
                  float strength = 1.0f);  // one dab (begins a stroke if none is open)
  // Dabs every quarter radius from `from` (exclusive: the previous dab) to `to`, the short way around
  // the tiling map: a mouse drag between two frames.
  PaintRect paint_line(const std::string& id, MapChannel channel, glm::vec2 from, glm::vec2 to, float radius,
                       float value, float strength = 1.0f);
  void end_stroke();
  bool in_stroke() const { return stroke_.has_value(); }

  // ---- Undo / redo
  bool can_undo() const { return !undo_.empty() || stroke_changed(); }
  bool can_redo() const { return !redo_.empty() && !stroke_changed(); }
  void undo();
  void redo();
  // The edit serial (edit_serial.h) of the next step to undo / redo, 0 when none: how an editor orders
  // the document's steps among its other edits.
  uint64_t undo_serial() const { return undo_.empty() ? 0 : undo_.back().serial; }
  uint64_t redo_serial() const { return redo_.empty() || stroke_changed() ? 0 : redo_.back().serial; }
  void clear_redo() { redo_.clear(); }  // an edit elsewhere in the editor's history
  std::string undo_label() const;  // "set coverage of fair_cumulus", "paint storm"; "" when none
  std::string redo_label() const;

  // Ids whose state changed (edited, undone, created, removed, renamed: both ids, reloaded, saved)
  // since the last call, sorted. For each: has(id) ? put(state(id)) : erase(id) mirrors the document.
  std::vector<std::string> take_changed();

  // ---- Dirty tracking (against the last save / open / reload)
  bool dirty() const;
  bool dirty(const std::string& id) const;  // also true for a removed state not yet saved
  std::vector<std::string> dirty_ids() const;

  // Writes every dirty state: its painting first (<id>.cloud_map.png, and the JSON's cloud_map.png set
  // to it), then the JSON; removed states' files (and paintings no state refers to) become PATH.bak;
  // the previous version of every replaced file is kept as PATH.bak. Each JSON is checked by the loader
  // before anything is written. All files are written under temporary names first and renamed only when
  // every write succeeded: on failure (read-only folder, full disk) this throws cumulo::Error naming the
  // file and the OS reason, and the files on disk, the states and the dirty flags are as before.
  // Pending conflicts of the states written are settled in favour of mine, and a file changed on disk
  // since the last poll_disk() is overwritten (its .bak keeps the other version).
  void save();

  // ---- Changes made by others. Cheap when nothing changed (a stat per file; the text is read and
  // compared only when the size or mtime moved; an edit of the same size within one tick of the file
  // system's clock is missed until the next change). A reload (or taking the disk's version of a conflict)
  // is not an undo step: it drops the undo and redo steps that touch the state, with every step older
  // (undo) or newer (redo) than them, so the history left never crosses the reload.
  std::vector<DiskEvent> poll_disk();
  std::vector<std::string> conflicts() const;  // ids with an unresolved Conflict
  // take_disk: the disk's version (or its deletion) replaces mine; else mine is kept and stays dirty
  // against the disk's version, to be written by the next save.
  void resolve_conflict(const std::string& id, bool take_disk);

 private:
  struct Entry {
    Json json;
    std::shared_ptr<const PaintedCloudMap> painted;
    clouds::weather::WeatherState state;  // validated from json, with painted
    bool same(const Entry& o) const { return painted == o.painted && json == o.json; }
  };
  using Slot = std::optional<Entry>;  // nullopt: the state does not exist
  struct Step {
    std::string label;
    std::map<std::string, Slot> before, after;
    std::string merge_key;  // "id\nparam" for a merged set
    uint64_t serial = 0;    // next_edit_serial() when made (a merge keeps the first)
  };
  struct Stroke {
    std::string id;
    Entry before;
  };
  struct DiskSeen {
    std::filesystem::file_time_type mtime;
    uintmax_t size = 0;
    std::string text;
  };

  WeatherDocument(std::filesystem::path folder, MapMaker make_map);
  Entry make_entry(const std::string& id, Json json, std::shared_ptr<const PaintedCloudMap> painted) const;
  const Entry& entry(const std::string& id) const;
  Slot slot(const std::string& id) const;
  void check_new_id(const std::string& id, const char* what) const;
  void apply(const std::map<std::string, Slot>& slots);
  void push(Step step);
  bool stroke_changed() const;
  void drop_history_of(const std::string& id);
  Entry disk_entry(const std::string& id, const std::string& text) const;  // throws when malformed
  void take_disk(const std::string& id, const Slot& disk);

  std::filesystem::path folder_;
  MapMaker make_map_;
  std::map<std::string, Entry> entries_;
  std::map<std::string, Entry> saved_;    // what the files hold (open, last save, reload)
  std::map<std::string, DiskSeen> seen_;  // last seen text of each *.json (malformed ones too)
  std::map<std::string, Slot> pending_;   // unresolved conflicts: the disk's version
  std::vector<std::string> problems_;
  std::vector<Step> undo_, redo_;  // back() is the next to undo / redo
  std::optional<Stroke> stroke_;
  std::set<std::string> changed_;
};

}  // namespace cumulo::editor
