#pragma once
// Component storage: one sparse set per component type.
//   sparse: entity index -> dense position (paged, so a high index does not allocate a huge array)
//   dense:  packed Entity handles and, in a parallel array, the components themselves.
// Removal swaps the last element into the hole, so the dense arrays stay contiguous for iteration.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"

namespace cumulo::ecs::detail {

class PoolBase {
 public:
  static constexpr uint32_t kAbsent = 0xFFFFFFFFu;
  static constexpr uint32_t kPageBits = 12;
  static constexpr uint32_t kPageSize = 1u << kPageBits;

  explicit PoolBase(std::string_view type_name) : type_name_(type_name) {}
  virtual ~PoolBase() = default;
  PoolBase(const PoolBase&) = delete;
  PoolBase& operator=(const PoolBase&) = delete;

  // Removes the component of the entity in slot `index` if present; returns whether it was there.
  virtual bool remove(uint32_t index) = 0;
  virtual void clear() = 0;

  // Pools only ever hold live entities (World::destroy empties every pool of the entity), so the slot
  // index is enough to answer membership.
  bool contains(uint32_t index) const { return position(index) != kAbsent; }
  uint32_t position(uint32_t index) const {
    uint32_t page = index >> kPageBits;
    if (page >= pages_.size() || !pages_[page]) return kAbsent;
    return pages_[page][index & (kPageSize - 1)];
  }
  // A snapshot of the sparse pages for a loop during which the pool's structure cannot change (a locked
  // view): lets the compiler keep the page table in registers instead of reloading it per entity.
  struct Lookup {
    const std::unique_ptr<uint32_t[]>* pages;
    size_t page_count;
    uint32_t position(uint32_t index) const {
      uint32_t page = index >> kPageBits;
      if (page >= page_count || !pages[page]) return kAbsent;
      return pages[page][index & (kPageSize - 1)];
    }
  };
  Lookup lookup() const { return Lookup{pages_.data(), pages_.size()}; }

  size_t size() const { return entities_.size(); }
  const std::vector<Entity>& entities() const { return entities_; }
  std::string_view type_name() const { return type_name_; }

 protected:
  uint32_t& slot(uint32_t index) {
    uint32_t page = index >> kPageBits;
    if (page >= pages_.size()) pages_.resize(page + 1);
    if (!pages_[page]) {
      pages_[page] = std::make_unique<uint32_t[]>(kPageSize);
      std::fill_n(pages_[page].get(), kPageSize, kAbsent);
    }
    return pages_[page][index & (kPageSize - 1)];
  }

  std::vector<Entity> entities_;
  std::vector<std::unique_ptr<uint32_t[]>> pages_;
  std::string_view type_name_;
};

template <typename T>
class Pool final : public PoolBase {
 public:
  using PoolBase::PoolBase;

  template <typename... Args>
  T& emplace(Entity e, Args&&... args) {
    // Parenthesised aggregate initialisation (C++20) lets plain structs be built from their members.
    data_.emplace_back(std::forward<Args>(args)...);
    slot(e.index) = uint32_t(entities_.size());
    entities_.push_back(e);
    return data_.back();
  }

  bool remove(uint32_t index) override {
    uint32_t pos = position(index);
    if (pos == kAbsent) return false;
    uint32_t last = uint32_t(entities_.size() - 1);
    if (pos != last) {
      data_[pos] = std::move(data_[last]);
      entities_[pos] = entities_[last];
      slot(entities_[pos].index) = pos;
    }
    data_.pop_back();
    entities_.pop_back();
    slot(index) = kAbsent;
    return true;
  }

  void clear() override {
    for (Entity e : entities_) slot(e.index) = kAbsent;
    entities_.clear();
    data_.clear();
  }

  T* find(uint32_t index) {
    uint32_t pos = position(index);
    return pos == kAbsent ? nullptr : &data_[pos];
  }
  const T* find(uint32_t index) const {
    uint32_t pos = position(index);
    return pos == kAbsent ? nullptr : &data_[pos];
  }
  T* data() { return data_.data(); }  // dense, parallel to entities()

 private:
  std::vector<T> data_;
};

}  // namespace cumulo::ecs::detail
