#pragma once
// Typed events, double-buffered per simulation step (the scheme of Bevy's Events<T>).
//
//   world.emit(LightningTriggered{pos, energy});            // any system, any phase
//
//   // a system that reacts: its reader remembers what it has already seen
//   sched.add_system(Phase::Update, "thunder",
//       [reader = EventReader<LightningTriggered>{}](World& w, const FrameContext&) mutable {
//         for (const LightningTriggered& ev : w.read(reader)) play_thunder(ev);
//       });
//
// World::update_events() (called by Scheduler::step at the start of every step) drops the events of
// the step before last and starts a new buffer. An event therefore survives one full step after the
// one it was emitted in, so every reader that runs once per step sees it exactly once, whatever the
// order of emitter and reader within the phases. A reader that skips steps loses old events and
// counts them in missed().
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace cumulo::ecs {

namespace detail {
class EventQueueBase {
 public:
  virtual ~EventQueueBase() = default;
  virtual void update() = 0;
};
}  // namespace detail

// Two spans seen as one sequence (older events first).
template <typename T>
class EventRange {
 public:
  EventRange() = default;
  EventRange(std::span<const T> a, std::span<const T> b) : a_(a), b_(b) {}

  size_t size() const { return a_.size() + b_.size(); }
  bool empty() const { return size() == 0; }
  const T& operator[](size_t i) const { return i < a_.size() ? a_[i] : b_[i - a_.size()]; }

  class iterator {
   public:
    iterator(const EventRange* r, size_t i) : r_(r), i_(i) {}
    const T& operator*() const { return (*r_)[i_]; }
    const T* operator->() const { return &(*r_)[i_]; }
    iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator==(const iterator& o) const { return i_ == o.i_; }

   private:
    const EventRange* r_;
    size_t i_;
  };
  iterator begin() const { return iterator(this, 0); }
  iterator end() const { return iterator(this, size()); }

 private:
  std::span<const T> a_, b_;
};

template <typename T>
class EventQueue final : public detail::EventQueueBase {
 public:
  void emit(T event) {
    current_.push_back(std::move(event));
    ++next_id_;
  }
  // Starts a new step: the previous buffer is dropped, the current one becomes the previous one.
  void update() override {
    previous_.swap(current_);
    current_.clear();
    previous_first_ = current_first_;
    current_first_ = next_id_;
  }

  std::span<const T> current() const { return current_; }    // emitted since the last update()
  std::span<const T> previous() const { return previous_; }  // emitted in the step before
  EventRange<T> all() const { return EventRange<T>(previous_, current_); }
  uint64_t next_id() const { return next_id_; }  // id the next emitted event will get
  uint64_t oldest_id() const { return previous_first_; }

  // Events with id >= first still held.
  EventRange<T> since(uint64_t first) const {
    auto tail = [first](std::span<const T> s, uint64_t s_first) {
      if (first <= s_first) return s;
      uint64_t skip = first - s_first;
      return skip >= s.size() ? std::span<const T>() : s.subspan(size_t(skip));
    };
    return EventRange<T>(tail(previous_, previous_first_), tail(current_, current_first_));
  }

 private:
  std::vector<T> previous_, current_;
  uint64_t previous_first_ = 0, current_first_ = 0, next_id_ = 0;
};

// Per-consumer cursor: read() returns the events this reader has not seen yet.
template <typename T>
class EventReader {
 public:
  EventRange<T> read(const EventQueue<T>& queue) {
    if (next_ < queue.oldest_id()) {
      missed_ += queue.oldest_id() - next_;
      next_ = queue.oldest_id();
    }
    EventRange<T> r = queue.since(next_);
    next_ = queue.next_id();
    return r;
  }
  uint64_t missed() const { return missed_; }

 private:
  uint64_t next_ = 0;
  uint64_t missed_ = 0;
};

}  // namespace cumulo::ecs
