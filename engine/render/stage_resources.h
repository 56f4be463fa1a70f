#pragma once
// Typed resources of one frame that a feature publishes for what comes after it (its later stages, other
// features, the engine's own passes), one value per type, found by type:
//
//   f.resources.publish(LightShadowMap{...});                      // at Stage::BeforeScene: a shadow caster
//   if (const auto* a = f.resources.find<AerialPerspective>()) ...  // from Stage::AfterOpaque
//
// The engine reads LightShadowMap (the geometry's key-light transmittance) and publishes
// AerialPerspective; a module may publish types of its own for another module.
#include <memory>
#include <typeindex>
#include <unordered_map>
#include <utility>

namespace cumulo::render {

class StageResources {
 public:
  template <typename T>
  void publish(T value) {
    values_[std::type_index(typeid(T))] = std::make_shared<T>(std::move(value));
  }
  template <typename T>
  const T* find() const {
    const auto it = values_.find(std::type_index(typeid(T)));
    return it == values_.end() ? nullptr : static_cast<const T*>(it->second.get());
  }

 private:
  std::unordered_map<std::type_index, std::shared_ptr<void>> values_;
};

}  // namespace cumulo::render
