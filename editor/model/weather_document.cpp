// WeatherDocument: edits, painting, undo/redo and dirty tracking. Opening, saving and watching the
// disk are in weather_document_disk.cpp.
#include "editor/model/weather_document.h"

#include "editor/model/edit_serial.h"

#include <algorithm>
#include <cmath>

#include "editor/model/edit_serial.h"
#include "editor/model/weather_params.h"
#include "engine/core/error.h"

namespace cumulo::editor {
namespace fs = std::filesystem;
using clouds::weather::WeatherState;

namespace {

// Enough for a long session; each step holds pointers to shared maps, not copies of them.
constexpr size_t kMaxUndoSteps = 512;

}  // namespace

bool valid_state_id(std::string_view id) {
  if (id.empty() || id.size() > 100) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string painted_map_file_name(const std::string& id) { return id + ".cloud_map.png"; }

WeatherDocument::WeatherDocument(fs::path folder, MapMaker make_map)
    : folder_(std::move(folder)), make_map_(std::move(make_map)) {}

WeatherDocument::Entry WeatherDocument::make_entry(const std::string& id, Json json,
                                                   std::shared_ptr<const PaintedCloudMap> painted) const {
  const JsonDocument doc(json, file(id).string());
  Entry e{std::move(json), std::move(painted), clouds::weather::weather_state_from_json(doc.view(), id, file(id))};
  e.state.cloud_map.painted = e.painted;
  return e;
}

const WeatherDocument::Entry& WeatherDocument::entry(const std::string& id) const {
  auto it = entries_.find(id);
  if (it == entries_.end()) {
    std::string known;
    for (const auto& [k, e] : entries_) known += (known.empty() ? "" : ", ") + k;
    fail("unknown weather state \"%s\" (known: %s)", id.c_str(), known.c_str());
  }
  return it->second;
}

WeatherDocument::Slot WeatherDocument::slot(const std::string& id) const {
  auto it = entries_.find(id);
  return it == entries_.end() ? Slot{} : Slot{it->second};
}

std::vector<std::string> WeatherDocument::ids() const {
  std::vector<std::string> out;
  for (const auto& [id, e] : entries_) out.push_back(id);
  return out;
}

const Json& WeatherDocument::json(const std::string& id) const { return entry(id).json; }
WeatherState WeatherDocument::state(const std::string& id) const { return entry(id).state; }

void WeatherDocument::check_new_id(const std::string& id, const char* what) const {
  if (!valid_state_id(id))
    fail("cannot %s \"%s\": a state id is letters, digits, '_' and '-' (it is the file name)", what, id.c_str());
  if (has(id)) fail("cannot %s \"%s\": a state with that id exists", what, id.c_str());
  // A file the document does not hold (one that did not load at open) is not overwritten silently.
  std::error_code ec;
  if (!saved_.count(id) && fs::exists(file(id), ec))
    fail("cannot %s \"%s\": %s exists (it did not load; fix or remove it first)", what, id.c_str(), file(id).c_str());
}

void WeatherDocument::apply(const std::map<std::string, Slot>& slots) {
  for (const auto& [id, s] : slots) {
    if (s)
      entries_.insert_or_assign(id, *s);
    else
      entries_.erase(id);
    changed_.insert(id);
  }
}

void WeatherDocument::push(Step step) {
  apply(step.after);
  step.serial = next_edit_serial();
  undo_.push_back(std::move(step));
  if (undo_.size() > kMaxUndoSteps) undo_.erase(undo_.begin());
  redo_.clear();
}

// ---- Edits

void WeatherDocument::set(const std::string& id, std::string_view param, const Json& value, bool merge) {
  end_stroke();
  const Entry& cur = entry(id);
  const ParamInfo* p = find_param(param);
  if (!p) {
    std::string known;
    for (const ParamInfo& q : weather_params()) known += (known.empty() ? "" : ", ") + q.path;
    fail("%s: unknown parameter \"%.*s\" (known: %s)", id.c_str(), int(param.size()), param.data(), known.c_str());
  }
  if (auto why = check_param_value(*p, value)) fail("%s: %s: %s", id.c_str(), p->path.c_str(), why->c_str());
  Json edited = cur.json;
  set_param(edited, p->path, normalize_param_value(*p, value));
  if (edited == cur.json) return;
  Entry next = [&] {
    try {
      return make_entry(id, std::move(edited), cur.painted);
    } catch (const Error& e) {
      fail("%s: %s: %s", id.c_str(), p->path.c_str(), e.what());
    }
  }();
  const std::string key = id + "\n" + p->path;
  if (merge && redo_.empty() && !undo_.empty() && undo_.back().merge_key == key) {
    Step& last = undo_.back();
    last.after[id] = next;
    apply(last.after);
    if (last.before.at(id)->same(next)) undo_.pop_back();  // dragged back to where it started
    return;
  }
  push({"set " + p->path + " of " + id, {{id, cur}}, {{id, std::move(next)}}, merge ? key : std::string()});
}

void WeatherDocument::create(const std::string& new_id, const std::string& template_id) {
  end_stroke();
  check_new_id(new_id, "create");
  Json j;
  if (template_id.empty()) {
    j = clouds::weather::weather_state_to_json(WeatherState{});
    j["$schema"] = "../schemas/weather.schema.json";
    for (const auto& [id, e] : entries_)  // the folder's own convention when it has one
      if (e.json.contains("$schema")) {
        j["$schema"] = e.json["$schema"];
        break;
      }
  } else {
    j = json(template_id);
    j.erase("description");
    if (j.contains("cloud_map") && j["cloud_map"].is_object()) j["cloud_map"].erase("png");
  }
  push({"create " + new_id, {{new_id, Slot{}}}, {{new_id, make_entry(new_id, std::move(j), nullptr)}}, {}});
}

void WeatherDocument::duplicate(const std::string& src, const std::string& new_id) {
  end_stroke();
  const Entry& e = entry(src);
  check_new_id(new_id, "duplicate as");
  push({"duplicate " + src + " as " + new_id,
        {{new_id, Slot{}}},
        {{new_id, make_entry(new_id, e.json, e.painted)}},
        {}});
}

void WeatherDocument::rename(const std::string& from, const std::string& to) {
  end_stroke();
  const Entry& e = entry(from);
  if (from == to) return;
  check_new_id(to, "rename to");
  push({"rename " + from + " to " + to,
        {{from, e}, {to, Slot{}}},
        {{from, Slot{}}, {to, make_entry(to, e.json, e.painted)}},
        {}});
}

void WeatherDocument::remove(const std::string& id) {
  end_stroke();
  push({"delete " + id, {{id, entry(id)}}, {{id, Slot{}}}, {}});
}

// ---- Painting

void WeatherDocument::begin_stroke(const std::string& id) {
  if (stroke_ && stroke_->id == id) return;
  end_stroke();
  stroke_ = Stroke{id, entry(id)};
}

bool WeatherDocument::stroke_changed() const {
  if (!stroke_) return false;
  auto it = entries_.find(stroke_->id);
  return it != entries_.end() && it->second.painted != stroke_->before.painted;
}

PaintRect WeatherDocument::paint(const std::string& id, MapChannel channel, glm::vec2 uv, float radius, float value,
                                 float strength) {
  return paint_line(id, channel, uv, uv, radius, value, strength);
}

PaintRect WeatherDocument::paint_line(const std::string& id, MapChannel channel, glm::vec2 from, glm::vec2 to,
                                      float radius, float value, float strength) {
  if (!(radius > 0.0f && radius <= 1.0f)) fail("%s: paint: radius %g is outside (0, 1]", id.c_str(), radius);
  begin_stroke(id);
  Entry& e = entries_.at(id);
  PaintedCloudMap map;
  if (e.painted) {
    map = *e.painted;
  } else {
    if (!make_map_) fail("%s: paint: the document has no map maker", id.c_str());
    map = make_map_(e.state.cloud_map);
    if (map.width == 0 || map.height == 0 || map.rgba.size() != size_t(map.width) * map.height * 4)
      fail("%s: paint: the map maker returned a %ux%u map with %zu bytes (expected width*height*4)", id.c_str(),
           map.width, map.height, map.rgba.size());
  }
  PaintRect changed;
  if (from == to) {
    changed = paint_dab(map, channel, to, radius, value, strength);
  } else {
    glm::vec2 d = to - from;
    d -= glm::round(d);  // the short way around the tiling map
    const float spacing = radius * 0.25f;
    const int n = std::max(1, int(std::ceil(glm::length(d) / spacing)));
    for (int i = 1; i <= n; ++i)
      changed.include(paint_dab(map, channel, from + d * (float(i) / float(n)), radius, value, strength));
  }
  // A fresh map even when only the base was made: the first dab of a procedural state.
  if (!changed.empty() || !e.painted) {
    e.painted = std::make_shared<const PaintedCloudMap>(std::move(map));
    e.state.cloud_map.painted = e.painted;
    changed_.insert(id);
  }
  return changed;
}

void WeatherDocument::end_stroke() {
  if (!stroke_) return;
  Stroke s = std::move(*stroke_);
  stroke_.reset();
  auto it = entries_.find(s.id);
  if (it == entries_.end() || it->second.painted == s.before.painted) return;
  // The pixels are already in place: record the step without applying it again.
  undo_.push_back({"paint " + s.id, {{s.id, s.before}}, {{s.id, it->second}}, {}, next_edit_serial()});
  if (undo_.size() > kMaxUndoSteps) undo_.erase(undo_.begin());
  redo_.clear();
}

// ---- Undo / redo

void WeatherDocument::undo() {
  end_stroke();
  if (undo_.empty()) return;
  Step s = std::move(undo_.back());
  undo_.pop_back();
  apply(s.before);
  redo_.push_back(std::move(s));
}

void WeatherDocument::redo() {
  end_stroke();
  if (redo_.empty()) return;
  Step s = std::move(redo_.back());
  redo_.pop_back();
  apply(s.after);
  undo_.push_back(std::move(s));
}

std::string WeatherDocument::undo_label() const {
  if (stroke_changed()) return "paint " + stroke_->id;
  return undo_.empty() ? std::string() : undo_.back().label;
}

std::string WeatherDocument::redo_label() const {
  return redo_.empty() || stroke_changed() ? std::string() : redo_.back().label;
}

void WeatherDocument::drop_history_of(const std::string& id) {
  auto touches = [&](const Step& s) { return s.before.count(id) > 0 || s.after.count(id) > 0; };
  for (std::vector<Step>* steps : {&undo_, &redo_}) {
    // Both stacks have their next step at the back: everything in front of the last step touching
    // the id is further from the present and goes with it.
    for (size_t i = steps->size(); i-- > 0;)
      if (touches((*steps)[i])) {
        steps->erase(steps->begin(), steps->begin() + ptrdiff_t(i) + 1);
        break;
      }
  }
}

std::vector<std::string> WeatherDocument::take_changed() {
  std::vector<std::string> out(changed_.begin(), changed_.end());
  changed_.clear();
  return out;
}

// ---- Dirty tracking

bool WeatherDocument::dirty(const std::string& id) const {
  auto cur = entries_.find(id);
  auto sav = saved_.find(id);
  if (cur == entries_.end() || sav == saved_.end()) return (cur == entries_.end()) != (sav == saved_.end());
  return !cur->second.same(sav->second);
}

std::vector<std::string> WeatherDocument::dirty_ids() const {
  std::set<std::string> all;
  for (const auto& [id, e] : entries_) all.insert(id);
  for (const auto& [id, e] : saved_) all.insert(id);
  std::vector<std::string> out;
  for (const std::string& id : all)
    if (dirty(id)) out.push_back(id);
  return out;
}

bool WeatherDocument::dirty() const { return !dirty_ids().empty(); }

}  // namespace cumulo::editor
