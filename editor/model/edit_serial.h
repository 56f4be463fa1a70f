#pragma once
// One sequence for every undoable edit of an editor session, the document's and the world's (a
// cloudscape dragged, the time of day set): undo takes whichever stack's top is newer, so the editor has
// one history without the document knowing the world.
#include <atomic>
#include <cstdint>

namespace cumulo::editor {

inline uint64_t next_edit_serial() {
  static std::atomic<uint64_t> last{0};
  return ++last;
}

}  // namespace cumulo::editor
