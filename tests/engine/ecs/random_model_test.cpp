// Randomized test of the World against a naive reference model (a std::map of optional values).
// Thousands of random operations per seed: create, destroy (live and stale handles), emplace,
// emplace_or_replace, remove, in-place writes, and views whose callbacks queue deferred
// create/destroy/emplace/remove, try forbidden direct changes and nest other views. The observable state
// (valid handles, every component value, pool sizes, view contents, handle uniqueness) is compared after
// every operation. Seeds are fixed so a failure reproduces; the failing seed and step are printed.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "engine/core/error.h"
#include "engine/ecs/serialize.h"
#include "engine/ecs/world.h"

namespace cumulo::ecs {
namespace {

struct CA {
  int v = 0;
};
struct CB {
  int v = 0;
};
struct CC {
  int v = 0;
};
constexpr int kTypes = 3;

// Calls fn.template operator()<T>() for the component type with index k.
template <typename F>
void with_type(int k, F&& fn) {
  switch (k) {
    case 0:
      fn.template operator()<CA>();
      break;
    case 1:
      fn.template operator()<CB>();
      break;
    default:
      fn.template operator()<CC>();
      break;
  }
}
template <typename T>
constexpr int index_of() {
  return std::is_same_v<T, CA> ? 0 : std::is_same_v<T, CB> ? 1 : 2;
}

struct Model {
  using Values = std::array<std::optional<int>, kTypes>;
  std::map<Entity, Values> alive;
  std::vector<Entity> dead;  // every handle ever destroyed: must stay invalid
  std::set<Entity> issued;   // every handle ever handed out: new ones must be new
  struct Pending {
    enum Kind { Create, Destroy, Emplace, Remove } kind;
    Entity e;
    int type = 0;
    int value = 0;
  };
  std::vector<Pending> pending;  // mirrors world.defer()

  void apply_pending() {
    for (const Pending& p : pending) {
      auto it = alive.find(p.e);
      switch (p.kind) {
        case Pending::Create:
          alive[p.e] = {};
          break;
        case Pending::Destroy:
          if (it != alive.end()) {
            alive.erase(it);
            dead.push_back(p.e);
          }
          break;
        case Pending::Emplace:
          if (it != alive.end()) it->second[p.type] = p.value;
          break;
        case Pending::Remove:
          if (it != alive.end()) it->second[p.type].reset();
          break;
      }
    }
    pending.clear();
  }
};

class RandomModel {
 public:
  explicit RandomModel(uint32_t seed) : rng_(seed) {
    with_type(0, [&]<typename T>() { register_type<T>("CA"); });
    with_type(1, [&]<typename T>() { register_type<T>("CB"); });
    with_type(2, [&]<typename T>() { register_type<T>("CC"); });
  }

  void run(int steps) {
    for (step_ = 0; step_ < steps; ++step_) {
      one_operation();
      compare();
      if (::testing::Test::HasFailure()) {
        ADD_FAILURE() << "first mismatch at step " << step_;
        return;
      }
    }
    // Show that the run exercised what it claims to (and guard against a generator that stopped doing so).
    printf(
        "  %d steps: %zu alive at end, %zu destroyed, %zu handles issued, %zu views, %zu entities visited, "
        "%zu deferred commands applied\n",
        steps, model_.alive.size(), model_.dead.size(), model_.issued.size(), views_, visits_, applied_);
    EXPECT_GT(visits_, size_t(steps));
    EXPECT_GT(applied_, size_t(steps) / 4);
    EXPECT_GT(model_.dead.size(), size_t(steps) / 20);
  }

 private:
  int rand(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  bool chance(int percent) { return rand(100) < percent; }

  std::optional<Entity> random_alive() {
    if (model_.alive.empty()) return std::nullopt;
    auto it = model_.alive.begin();
    std::advance(it, rand(int(model_.alive.size())));
    return it->first;
  }
  std::optional<Entity> random_dead() {
    if (model_.dead.empty()) return std::nullopt;
    return model_.dead[rand(int(model_.dead.size()))];
  }
  void note_new(Entity e) {
    EXPECT_TRUE(model_.issued.insert(e).second) << "handle reissued: " << e.index << "v" << e.generation;
  }

  template <typename Fn>
  void expect_error(Fn&& fn, const char* what) {
    try {
      fn();
      ADD_FAILURE() << what << ": no error at step " << step_;
    } catch (const Error&) {
    }
  }

  void one_operation() {
    // Keep the population around 150 so views visit many entities while stale handles and slot reuse
    // still happen a lot (creation slows down above that).
    int op = rand(100);
    bool grow = model_.alive.size() < 150;
    if (op < 25) {
      if (grow || op < 5) {
        Entity e = world_.create();
        note_new(e);
        model_.alive[e] = {};
      } else {
        iterate();
      }
    } else if (op < 30) {
      if (auto e = random_alive()) {
        world_.destroy(*e);
        model_.alive.erase(*e);
        model_.dead.push_back(*e);
      }
    } else if (op < 33) {
      if (auto e = random_dead()) {
        expect_error([&] { world_.destroy(*e); }, "destroy(stale)");
        expect_error([&] { with_type(rand(kTypes), [&]<typename T>() { world_.get<T>(*e); }); }, "get(stale)");
        with_type(rand(kTypes), [&]<typename T>() { EXPECT_EQ(world_.try_get<T>(*e), nullptr); });
      }
    } else if (op < 50) {
      if (auto e = random_alive()) {
        int k = rand(kTypes), v = rand(1000);
        with_type(k, [&]<typename T>() {
          if (model_.alive[*e][k]) {
            expect_error([&] { world_.emplace<T>(*e, v); }, "emplace(existing)");
          } else {
            EXPECT_EQ(world_.emplace<T>(*e, v).v, v);
            model_.alive[*e][k] = v;
          }
        });
      }
    } else if (op < 56) {
      if (auto e = random_alive()) {
        int k = rand(kTypes), v = rand(1000);
        with_type(k, [&]<typename T>() { world_.emplace_or_replace<T>(*e, v); });
        model_.alive[*e][k] = v;
      }
    } else if (op < 66) {
      if (auto e = random_alive()) {
        int k = rand(kTypes);
        bool had = model_.alive[*e][k].has_value();
        with_type(k, [&]<typename T>() { EXPECT_EQ(world_.remove<T>(*e), had); });
        model_.alive[*e][k].reset();
      }
    } else if (op < 72) {
      if (auto e = random_alive()) {
        int k = rand(kTypes), v = rand(1000);
        with_type(k, [&]<typename T>() {
          if (model_.alive[*e][k]) {
            world_.get<T>(*e).v = v;
            model_.alive[*e][k] = v;
          } else {
            expect_error([&] { world_.get<T>(*e); }, "get(missing)");
          }
        });
      }
    } else if (op < 76) {
      // Deferred outside any view: nothing happens until flush().
      for (int i = rand(4); i >= 0; --i) queue_random_command({});
      compare_pending_invisible();
      world_.flush();
      applied_ += model_.pending.size();
      model_.apply_pending();
    } else if (op < 77 && chance(20)) {
      world_.clear();
      for (auto& [e, v] : model_.alive) model_.dead.push_back(e);
      model_.alive.clear();
    } else {
      iterate();
    }
  }

  // A command on a random target: a live entity, one reserved in this batch, or (rarely) a stale
  // handle, which must be refused at once and not queued.
  void queue_random_command(const std::vector<Entity>& reserved) {
    using P = Model::Pending;
    int kind = rand(4);
    if (kind == 0) {
      Entity e = world_.defer().create();
      note_new(e);
      EXPECT_FALSE(world_.valid(e));
      model_.pending.push_back({P::Create, e});
      if (chance(70)) {
        int k = rand(kTypes), v = rand(1000);
        with_type(k, [&]<typename T>() { world_.defer().emplace<T>(e, v); });
        model_.pending.push_back({P::Emplace, e, k, v});
      }
      return;
    }
    std::optional<Entity> target = random_alive();
    if (!reserved.empty() && chance(20)) target = reserved[rand(int(reserved.size()))];
    if (chance(5)) {
      if (auto d = random_dead()) {
        // Stale at queue time (not merely destroyed by an earlier queued command): refused now.
        if (!model_.alive.count(*d)) {
          expect_error([&] { world_.defer().destroy(*d); }, "defer().destroy(stale)");
          return;
        }
      }
    }
    if (!target) return;
    int k = rand(kTypes), v = rand(1000);
    if (kind == 1) {
      world_.defer().destroy(*target);
      model_.pending.push_back({P::Destroy, *target});
    } else if (kind == 2) {
      with_type(k, [&]<typename T>() { world_.defer().emplace<T>(*target, v); });
      model_.pending.push_back({P::Emplace, *target, k, v});
    } else {
      with_type(k, [&]<typename T>() { world_.defer().remove<T>(*target); });
      model_.pending.push_back({P::Remove, *target, k});
    }
  }

  // Queued commands are invisible until applied.
  void compare_pending_invisible() {
    for (const auto& p : model_.pending)
      if (p.kind == Model::Pending::Create) EXPECT_FALSE(world_.valid(p.e));
    EXPECT_EQ(world_.alive_count(), model_.alive.size());
  }

  // The set of entities the model says a view over the types in `mask` visits.
  std::set<Entity> expected_matches(std::array<bool, kTypes> mask, std::array<bool, kTypes> without = {}) const {
    std::set<Entity> out;
    for (const auto& [e, vals] : model_.alive) {
      bool all = true;
      for (int k = 0; k < kTypes; ++k) all &= (!mask[k] || vals[k].has_value()) && !(without[k] && vals[k]);
      if (all) out.insert(e);
    }
    return out;
  }

  template <typename T>
  void check_component(Entity e, const T& c) {
    const auto& want = model_.alive.at(e)[index_of<T>()];
    EXPECT_TRUE(want.has_value());
    if (want) EXPECT_EQ(c.v, *want);
  }

  // Body run for each visited entity of any view shape.
  void visit(Entity e, std::set<Entity>& visited, std::vector<Entity>& reserved) {
    EXPECT_TRUE(visited.insert(e).second) << "visited twice";
    ++visits_;
    EXPECT_TRUE(world_.iterating());
    int r = rand(100);
    if (r < 25) {
      queue_random_command(reserved);
      if (!model_.pending.empty() && model_.pending.back().kind == Model::Pending::Create)
        reserved.push_back(model_.pending.back().e);
      // A queued destroy has not happened yet.
      EXPECT_TRUE(world_.valid(e));
    } else if (r < 30) {
      int k = rand(kTypes);
      with_type(k, [&]<typename T>() {
        if (chance(50))
          expect_error([&] { world_.remove<T>(e); }, "remove during each");
        else if (!model_.alive.at(e)[k])
          expect_error([&] { world_.emplace<T>(e); }, "emplace during each");
      });
      if (chance(20)) expect_error([&] { world_.destroy(e); }, "destroy during each");
    } else if (r < 33) {
      // A nested read-only view sees the same (unchanged) structure and does not apply the queue.
      size_t pending = world_.defer().size();
      size_t n = 0;
      world_.view<const CC>().each([&](Entity, const CC&) { ++n; });
      EXPECT_EQ(n, expected_matches({false, false, true}).size());
      EXPECT_EQ(world_.defer().size(), pending);
    }
  }

  void iterate() {
    std::set<Entity> visited;
    std::vector<Entity> reserved;
    std::array<bool, kTypes> mask{}, without{};
    switch (rand(5)) {
      case 4:
        mask = {false, true, false};
        without = {true, false, true};
        world_.view<CB>(exclude<CA, CC>).each([&](Entity e, CB& b) {
          check_component(e, b);
          visit(e, visited, reserved);
        });
        break;
      case 0:
        mask = {true, true, false};
        world_.view<const CA, CB>().each([&](Entity e, const CA& a, CB& b) {
          check_component(e, a);
          check_component(e, b);
          if (chance(30)) model_.alive.at(e)[1] = ++b.v;  // in-place write through the mutable one
          visit(e, visited, reserved);
        });
        break;
      case 1:
        mask = {true, false, false};
        world_.view<CA>().each([&](Entity e, CA& a) {
          check_component(e, a);
          visit(e, visited, reserved);
        });
        break;
      case 2:
        mask = {false, true, true};
        world_.view<CB, const CC>().each([&](Entity e, CB& b, const CC& c) {
          check_component(e, b);
          check_component(e, c);
          visit(e, visited, reserved);
        });
        break;
      default:
        mask = {true, true, true};
        world_.view<const CA, const CB, CC>().each([&](Entity e, const CA& a, const CB& b, CC& c) {
          check_component(e, a);
          check_component(e, b);
          check_component(e, c);
          if (chance(30)) model_.alive.at(e)[2] = c.v = rand(1000);
          visit(e, visited, reserved);
        });
    }
    // Exactly the matching set as it was when iteration began (queued changes are not visible yet).
    EXPECT_EQ(visited, expected_matches(mask, without));
    EXPECT_FALSE(world_.iterating());
    EXPECT_TRUE(world_.defer().empty()) << "the outermost each() applies the queue";
    ++views_;
    applied_ += model_.pending.size();
    model_.apply_pending();
  }

  void compare() {
    ASSERT_EQ(world_.alive_count(), model_.alive.size());
    std::array<size_t, kTypes> counts{};
    for (const auto& [e, vals] : model_.alive) {
      ASSERT_TRUE(world_.valid(e));
      for (int k = 0; k < kTypes; ++k) {
        if (vals[k]) ++counts[k];
        with_type(k, [&]<typename T>() {
          const T* c = world_.try_get<T>(e);
          ASSERT_EQ(c != nullptr, vals[k].has_value()) << "entity " << e.index << " type " << k;
          if (c) EXPECT_EQ(c->v, *vals[k]);
          EXPECT_EQ(world_.has<T>(e), vals[k].has_value());
        });
      }
    }
    EXPECT_EQ(world_.count<CA>(), counts[0]);
    EXPECT_EQ(world_.count<CB>(), counts[1]);
    EXPECT_EQ(world_.count<CC>(), counts[2]);
    // A sample of stale handles (all of them now and then).
    size_t n = step_ % 64 == 0 ? model_.dead.size() : std::min<size_t>(8, model_.dead.size());
    for (size_t i = 0; i < n; ++i) {
      Entity d = step_ % 64 == 0 ? model_.dead[i] : model_.dead[rand(int(model_.dead.size()))];
      EXPECT_FALSE(world_.valid(d));
    }
    if (step_ % 500 == 0) compare_serialized();
    if (step_ % 32 == 0) {
      std::set<Entity> listed;
      world_.each_entity([&](Entity e) { listed.insert(e); });
      std::set<Entity> want;
      for (const auto& [e, v] : model_.alive) want.insert(e);
      EXPECT_EQ(listed, want);
    }
  }

  template <typename T>
  void register_type(const char* name) {
    registry_.register_component<T>(
        name,
        [](const T& c) {
          return Json{{"v", c.v}};
        },
        [](const JsonView& v) { return T{v["v"].as<int>()}; });
  }

  // serialize_world -> load_entities into a fresh world -> serialize again: same JSON, and the model's
  // entities in slot order.
  void compare_serialized() {
    Json saved = serialize_world(world_, registry_);
    ASSERT_EQ(saved.size(), model_.alive.size());
    size_t i = 0;
    world_.each_entity([&](Entity e) {
      const auto& vals = model_.alive.at(e);
      const Json& comps = saved[i++]["components"];
      const char* names[kTypes] = {"CA", "CB", "CC"};
      for (int k = 0; k < kTypes; ++k) {
        ASSERT_EQ(comps.contains(names[k]), vals[k].has_value());
        if (vals[k]) EXPECT_EQ(comps[names[k]]["v"].get<int>(), *vals[k]);
      }
    });
    World copy;
    JsonDocument doc(saved, "random.json");
    load_entities(doc.view(), copy, registry_);
    EXPECT_EQ(serialize_world(copy, registry_), saved);
  }

  ComponentRegistry registry_;
  std::mt19937 rng_;
  World world_;
  Model model_;
  int step_ = 0;
  size_t views_ = 0, visits_ = 0, applied_ = 0;
};

class EcsRandomModel : public ::testing::TestWithParam<uint32_t> {};

TEST_P(EcsRandomModel, MatchesNaiveModel) {
  RandomModel m(GetParam());
  m.run(10000);
}

INSTANTIATE_TEST_SUITE_P(Seeds, EcsRandomModel, ::testing::Values(1u, 2u, 3u, 42u, 1234u, 99991u));

}  // namespace
}  // namespace cumulo::ecs
