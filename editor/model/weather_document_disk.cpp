// WeatherDocument and the disk: open, save (all or nothing, with .bak copies) and the watch on files
// changed by others.
#include <algorithm>
#include <system_error>

#include "editor/model/weather_document.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/core/png.h"
#include "modules/clouds/weather/weather_fields.h"

namespace cumulo::editor {
namespace fs = std::filesystem;

namespace {

// The key order of the shipped files, per object path (the field table's); keys not listed follow in
// their own order.
const std::vector<std::string>* canonical_keys(const std::string& path) {
  const clouds::weather::WeatherObject* o = clouds::weather::find_weather_object(path);
  return o ? &o->keys : nullptr;
}

nlohmann::ordered_json ordered(const Json& j, const std::string& path) {
  if (j.is_array()) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const Json& e : j) a.push_back(ordered(e, path));
    return a;
  }
  if (!j.is_object()) return nlohmann::ordered_json::parse(j.dump());
  nlohmann::ordered_json o = nlohmann::ordered_json::object();
  auto child = [&](const std::string& k) { return path.empty() ? k : path + "." + k; };
  if (const auto* keys = canonical_keys(path))
    for (const std::string& k : *keys)
      if (j.contains(k)) o[k] = ordered(j[k], child(k));
  for (const auto& [k, v] : j.items())
    if (!o.contains(k)) o[k] = ordered(v, child(k));
  return o;
}

bool is_state_file(const fs::directory_entry& e) {
  std::error_code ec;
  return e.path().extension() == ".json" && e.is_regular_file(ec);
}

std::string json_png(const Json& j) {
  if (j.contains("cloud_map") && j["cloud_map"].is_object() && j["cloud_map"].contains("png") &&
      j["cloud_map"]["png"].is_string())
    return j["cloud_map"]["png"].get<std::string>();
  return {};
}

void add_backup(FileSet& set, const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return;
  fs::path bak = path;
  bak += ".bak";
  set.add(bak, read_file_bytes(path));
}

}  // namespace

std::string weather_state_text(const Json& state) { return ordered(state, "").dump(2) + "\n"; }

const char* disk_event_name(DiskEvent::Kind k) {
  switch (k) {
    case DiskEvent::Kind::Reloaded:
      return "reloaded";
    case DiskEvent::Kind::Conflict:
      return "conflict";
    case DiskEvent::Kind::Malformed:
      return "malformed";
    case DiskEvent::Kind::Added:
      return "added";
    case DiskEvent::Kind::Removed:
      return "removed";
  }
  return "?";
}

WeatherDocument::Entry WeatherDocument::disk_entry(const std::string& id, const std::string& text) const {
  const JsonDocument doc = parse_json_text(text, file(id).string());
  return make_entry(id, doc.json(), nullptr);
}

WeatherDocument WeatherDocument::open(const fs::path& folder, MapMaker make_map) {
  WeatherDocument doc(folder, std::move(make_map));
  // A save killed midway (by a crash, a power cut, SIGKILL): its journal finishes it, its stray temporaries go. Said
  // in the log, so the person knows which files the last save left.
  for (const std::string& line : recover_file_sets(folder)) LOG_INFO("%s", line.c_str());
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec) fail("%s: cannot list the weather folder: %s", folder.c_str(), ec.message().c_str());
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : it)
    if (is_state_file(e)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    const std::string id = f.stem().string();
    if (!valid_state_id(id)) {
      doc.problems_.push_back(f.string() + ": not a state id (letters, digits, '_' and '-'); skipped");
      continue;
    }
    try {
      DiskSeen seen{fs::last_write_time(f), fs::file_size(f), read_file_text(f)};
      doc.seen_[id] = seen;  // a malformed file too: it is reported again only when it changes
      Entry e = doc.disk_entry(id, seen.text);
      doc.saved_[id] = e;
      doc.entries_[id] = std::move(e);
    } catch (const Error& e) {
      doc.problems_.push_back(e.what());
    } catch (const fs::filesystem_error& e) {
      doc.problems_.push_back(f.string() + ": " + e.code().message());
    }
  }
  return doc;
}

// ---- Saving

void WeatherDocument::save() {
  end_stroke();
  struct Write {
    std::string id;
    Json json;
    bool png = false;  // the painting is written too
    std::string text;
  };
  std::vector<Write> writes;
  std::vector<std::string> removed;
  for (const std::string& id : dirty_ids()) {
    auto cur = entries_.find(id);
    if (cur == entries_.end()) {
      removed.push_back(id);
      continue;
    }
    const Entry& e = cur->second;
    Write w{id, e.json};
    if (e.painted) {
      w.json["cloud_map"]["png"] = painted_map_file_name(id);
      auto sav = saved_.find(id);
      std::error_code ec;
      w.png = sav == saved_.end() || sav->second.painted != e.painted ||
              !fs::is_regular_file(folder_ / painted_map_file_name(id), ec);
    }
    // Never write a file that would not load: the loader checks it (the PNG being written is ours).
    Json check = w.json;
    if (w.png) check["cloud_map"].erase("png");
    try {
      make_entry(id, check, nullptr);
    } catch (const Error& err) {
      fail("save: %s would not load: %s", file(id).c_str(), err.what());
    }
    w.text = weather_state_text(w.json);
    writes.push_back(std::move(w));
  }
  // Paintings of removed states go to .bak too, unless a state still refers to them (a duplicate or a
  // renamed state that was not painted since).
  std::set<std::string> referenced;
  for (const auto& [id, e] : entries_) {
    auto w = std::find_if(writes.begin(), writes.end(), [&](const Write& x) { return x.id == id; });
    referenced.insert(json_png(w == writes.end() ? e.json : w->json));
  }
  std::vector<fs::path> retire;
  for (const std::string& id : removed) {
    retire.push_back(file(id));
    if (!referenced.count(painted_map_file_name(id))) retire.push_back(folder_ / painted_map_file_name(id));
  }

  try {
    FileSet set;
    for (const Write& w : writes) {
      if (w.png) {
        const PaintedCloudMap& m = *entries_.at(w.id).painted;
        const fs::path png = folder_ / painted_map_file_name(w.id);
        add_backup(set, png);
        set.add(png, encode_png(m.rgba.data(), m.width, m.height, 4));
      }
      add_backup(set, file(w.id));
      set.add(file(w.id), w.text);
    }
    for (const fs::path& p : retire) add_backup(set, p);
    set.commit();
  } catch (const Error& e) {
    fail("save failed: %s", e.what());
  }
  // The new files are in place; the retired ones have their .bak copy already.
  std::string leftovers;
  for (const fs::path& p : retire) {
    std::error_code ec;
    if (fs::exists(p, ec) && !fs::remove(p, ec) && ec) leftovers += "\n  " + p.string() + ": " + ec.message();
  }
  for (const std::string& id : removed) {
    saved_.erase(id);
    seen_.erase(id);
    pending_.erase(id);
  }
  for (Write& w : writes) {
    Entry& e = entries_.at(w.id);
    if (w.json != e.json) {
      e = make_entry(w.id, std::move(w.json), e.painted);  // the cloud_map.png now exists
      changed_.insert(w.id);
    }
    saved_.insert_or_assign(w.id, e);
    pending_.erase(w.id);
    std::error_code ec;
    seen_[w.id] = DiskSeen{fs::last_write_time(file(w.id), ec), fs::file_size(file(w.id), ec), std::move(w.text)};
  }
  if (!leftovers.empty()) fail("saved, but could not remove the files of deleted states:%s", leftovers.c_str());
}

// ---- Changes made by others

void WeatherDocument::take_disk(const std::string& id, const Slot& disk) {
  if (stroke_ && stroke_->id == id) stroke_.reset();  // the stroke's pixels go with the state
  if (disk) {
    entries_.insert_or_assign(id, *disk);
    saved_.insert_or_assign(id, *disk);
  } else {
    entries_.erase(id);
    saved_.erase(id);
  }
  changed_.insert(id);
  drop_history_of(id);
}

std::vector<DiskEvent> WeatherDocument::poll_disk() {
  std::vector<DiskEvent> events;
  using K = DiskEvent::Kind;
  std::set<std::string> present;
  std::error_code ec;
  fs::directory_iterator it(folder_, ec);
  if (ec) return events;  // the folder is gone for now: nothing to conclude from it
  for (const fs::directory_entry& de : it) {
    if (!is_state_file(de)) continue;
    const std::string id = de.path().stem().string();
    if (!valid_state_id(id)) continue;
    present.insert(id);
    DiskSeen now{fs::last_write_time(de.path(), ec), fs::file_size(de.path(), ec), {}};
    if (ec) continue;
    auto seen = seen_.find(id);
    if (seen != seen_.end() && seen->second.mtime == now.mtime && seen->second.size == now.size) continue;
    try {
      now.text = read_file_text(de.path());
    } catch (const Error&) {
      continue;  // being replaced right now: the next poll sees the result
    }
    const bool known = seen != seen_.end();
    const bool same_text = known && seen->second.text == now.text;
    seen_[id] = now;
    if (same_text) continue;
    Slot disk;
    try {
      disk = disk_entry(id, now.text);
    } catch (const Error& e) {
      events.push_back({K::Malformed, id, e.what()});
      continue;
    }
    auto sav = saved_.find(id);
    if (sav != saved_.end() && sav->second.json == disk->json) continue;  // reformatted, or touched
    if (dirty(id) || (stroke_ && stroke_->id == id)) {
      pending_[id] = disk;
      events.push_back({K::Conflict, id, file(id).string() + ": changed on disk while edited here"});
      continue;
    }
    const bool existed = has(id);
    take_disk(id, disk);
    events.push_back({existed ? K::Reloaded : K::Added, id, file(id).string() + (existed ? ": reloaded" : ": added")});
  }
  for (auto s = seen_.begin(); s != seen_.end();) {
    const std::string id = s->first;
    if (present.count(id)) {
      ++s;
      continue;
    }
    s = seen_.erase(s);
    if (!saved_.count(id)) continue;  // a malformed file went away
    if (dirty(id) || (stroke_ && stroke_->id == id)) {
      pending_[id] = Slot{};
      events.push_back({K::Conflict, id, file(id).string() + ": deleted on disk while edited here"});
    } else {
      take_disk(id, Slot{});
      events.push_back({K::Removed, id, file(id).string() + ": deleted on disk"});
    }
  }
  return events;
}

std::vector<std::string> WeatherDocument::conflicts() const {
  std::vector<std::string> out;
  for (const auto& [id, s] : pending_) out.push_back(id);
  return out;
}

void WeatherDocument::resolve_conflict(const std::string& id, bool take) {
  auto it = pending_.find(id);
  if (it == pending_.end()) fail("%s: no conflict with the disk to resolve", id.c_str());
  const Slot disk = it->second;
  pending_.erase(it);
  if (take) {
    take_disk(id, disk);
    return;
  }
  // Mine stays; it is now dirty against what the disk holds, so the next save writes it.
  if (disk)
    saved_.insert_or_assign(id, *disk);
  else
    saved_.erase(id);
}

}  // namespace cumulo::editor
