// Google Benchmark for the ECS: iterating 1M entities with 2 components through view<const A, B>, and the
// cost of the structural operations around it. Run: build-ecs/tests/engine/ecs/ecs_bench
// (CTest only runs it once with --benchmark_min_time=0.01 as a smoke test; numbers come from a manual run.)
#include <benchmark/benchmark.h>

#include <vector>

#include "engine/ecs/world.h"

namespace cumulo::ecs {
namespace {

struct Velocity {
  float x, y, z;
};
struct Position {
  float x, y, z;
};
struct Unrelated {
  int v;
};

constexpr int kEntities = 1'000'000;

void fill(World& w, int n, int every_second_velocity) {
  for (int i = 0; i < n; ++i) {
    Entity e = w.create();
    w.emplace<Position>(e, 0.0f, 0.0f, 0.0f);
    if (!every_second_velocity || i % 2 == 0) w.emplace<Velocity>(e, 1.0f, 2.0f, float(i % 7));
  }
}

// The headline number: 1M entities, both components on every entity.
void BM_View2_1M(benchmark::State& state) {
  World w;
  fill(w, kEntities, 0);
  const float dt = 1.0f / 60.0f;
  for (auto _ : state) {
    w.view<const Velocity, Position>().each([dt](const Velocity& v, Position& p) {
      p.x += v.x * dt;
      p.y += v.y * dt;
      p.z += v.z * dt;
    });
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kEntities);
}
BENCHMARK(BM_View2_1M)->Unit(benchmark::kMillisecond);

// Same with the Entity handle passed too.
void BM_View2_1M_WithEntity(benchmark::State& state) {
  World w;
  fill(w, kEntities, 0);
  uint64_t sum = 0;
  for (auto _ : state) {
    w.view<const Velocity, Position>().each([&sum](Entity e, const Velocity& v, Position& p) {
      p.x += v.x;
      sum += e.index;
    });
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kEntities);
}
BENCHMARK(BM_View2_1M_WithEntity)->Unit(benchmark::kMillisecond);

// 1M positions, velocity on every second one: the view leads with the smaller Velocity pool.
void BM_View2_1M_HalfMatch(benchmark::State& state) {
  World w;
  fill(w, kEntities, 1);
  for (auto _ : state) {
    w.view<Position, const Velocity>().each([](Position& p, const Velocity& v) { p.x += v.x; });
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kEntities / 2);
}
BENCHMARK(BM_View2_1M_HalfMatch)->Unit(benchmark::kMillisecond);

// Baseline: the same update over two plain arrays (the floor a sparse-set view can approach).
void BM_PlainArrays_1M(benchmark::State& state) {
  std::vector<Velocity> vel(kEntities, Velocity{1.0f, 2.0f, 3.0f});
  std::vector<Position> pos(kEntities, Position{0, 0, 0});
  const float dt = 1.0f / 60.0f;
  for (auto _ : state) {
    for (int i = 0; i < kEntities; ++i) {
      pos[i].x += vel[i].x * dt;
      pos[i].y += vel[i].y * dt;
      pos[i].z += vel[i].z * dt;
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kEntities);
}
BENCHMARK(BM_PlainArrays_1M)->Unit(benchmark::kMillisecond);

// Structural cost: create 100k entities with two components, then destroy them all.
void BM_CreateDestroy_100k(benchmark::State& state) {
  World w;
  std::vector<Entity> es(100'000);
  for (auto _ : state) {
    for (Entity& e : es) {
      e = w.create();
      w.emplace<Position>(e, 1.0f, 2.0f, 3.0f);
      w.emplace<Velocity>(e, 1.0f, 2.0f, 3.0f);
    }
    for (Entity e : es) w.destroy(e);
  }
  state.SetItemsProcessed(state.iterations() * int64_t(es.size()));
}
BENCHMARK(BM_CreateDestroy_100k)->Unit(benchmark::kMillisecond);

// Deferred destroy of every tenth entity during iteration, applied when each() returns, then refilled.
void BM_DeferredDestroy_100k(benchmark::State& state) {
  World w;
  fill(w, 100'000, 0);
  w.emplace<Unrelated>(w.create(), 0);
  for (auto _ : state) {
    int i = 0;
    w.view<Position>().each([&](Entity e, Position&) {
      if (++i % 10 == 0) w.defer().destroy(e);
    });
    state.PauseTiming();
    while (w.count<Position>() < 100'000) w.emplace<Position>(w.create(), 0.0f, 0.0f, 0.0f);
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * 100'000);
}
BENCHMARK(BM_DeferredDestroy_100k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cumulo::ecs

BENCHMARK_MAIN();
