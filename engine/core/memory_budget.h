#pragma once
// The memory a command may plan to use for its volumes. Bakes and imports compute what they will
// allocate from the dimensions before allocating anything and call check_memory_budget(), so an
// oversized request (a 4096^3 grid, each axis within its own limit) is refused with the option or
// file that asked for it instead of ending in std::bad_alloc, which names neither.
//
//   check_memory_budget(voxels * kBakeBytesPerVoxel, strf("%s: a %ux%ux%u bake grid (--dims)", file, x, y, z));
#include <cstdint>
#include <initializer_list>
#include <string>

namespace cumulo {

// $CUMULO_MEMORY_BUDGET_MB when set, else three quarters of the physical memory.
uint64_t memory_budget_bytes();

// Throws "WHAT needs about N GiB, over the memory budget of M GiB (CUMULO_MEMORY_BUDGET_MB)".
void check_memory_budget(uint64_t bytes, const std::string& what);

// a * b * c ... without wrapping: saturates at UINT64_MAX, which no budget admits.
uint64_t saturating_product(std::initializer_list<uint64_t> factors);

}  // namespace cumulo
