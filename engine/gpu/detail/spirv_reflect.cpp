#include "engine/gpu/detail/spirv_reflect.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <unordered_map>

#include "engine/core/error.h"

namespace cumulo::gpu::detail {

namespace {

enum Op : uint32_t {
  OpName = 5,
  OpExecutionMode = 16,
  OpExecutionModeId = 331,
  OpTypeBool = 20,
  OpTypeInt = 21,
  OpTypeFloat = 22,
  OpTypeVector = 23,
  OpTypeMatrix = 24,
  OpTypeImage = 25,
  OpTypeSampler = 26,
  OpTypeSampledImage = 27,
  OpTypeArray = 28,
  OpTypeRuntimeArray = 29,
  OpTypeStruct = 30,
  OpTypePointer = 32,
  OpConstant = 43,
  OpVariable = 59,
  OpDecorate = 71,
  OpMemberDecorate = 72,
  OpTypeAccelerationStructure = 5341,
};
enum Decoration : uint32_t {
  Block = 2,
  BufferBlock = 3,
  ArrayStride = 6,
  MatrixStride = 7,
  Binding = 33,
  DescriptorSet = 34,
  Offset = 35
};
enum StorageClass : uint32_t { UniformConstant = 0, Uniform = 2, PushConstant = 9, StorageBuffer = 12 };

struct Type {
  uint32_t op = 0;
  std::vector<uint32_t> args;  // operands after the result id
};

struct Parser {
  std::unordered_map<uint32_t, Type> types;
  std::unordered_map<uint32_t, uint64_t> constants;
  std::unordered_map<uint32_t, std::string> names;
  std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> decorations;  // id -> decoration -> value
  std::map<std::pair<uint32_t, uint32_t>, std::map<uint32_t, uint32_t>> member_decorations;
  std::string where;

  bool has(uint32_t id, uint32_t dec) const {
    auto it = decorations.find(id);
    return it != decorations.end() && it->second.count(dec);
  }
  uint32_t get(uint32_t id, uint32_t dec, uint32_t fallback = 0) const {
    auto it = decorations.find(id);
    if (it == decorations.end()) return fallback;
    auto d = it->second.find(dec);
    return d == it->second.end() ? fallback : d->second;
  }
  const Type& type(uint32_t id) const {
    auto it = types.find(id);
    if (it == types.end()) fail("%s: SPIR-V references unknown type %%%u", where.c_str(), id);
    return it->second;
  }

  uint64_t size_of(uint32_t id, uint32_t matrix_stride) const {
    const Type& t = type(id);
    switch (t.op) {
      case OpTypeBool:
        return 4;
      case OpTypeInt:
      case OpTypeFloat:
        return t.args[0] / 8;
      case OpTypeVector:
        return size_of(t.args[0], 0) * t.args[1];
      case OpTypeMatrix:
        return uint64_t(t.args[1]) * (matrix_stride ? matrix_stride : size_of(t.args[0], 0));
      case OpTypeArray: {
        uint64_t n = constants.count(t.args[1]) ? constants.at(t.args[1]) : 1;
        uint32_t stride = get(id, ArrayStride);
        return n * (stride ? stride : size_of(t.args[0], matrix_stride));
      }
      case OpTypeStruct: {
        uint64_t size = 0;
        for (uint32_t m = 0; m < t.args.size(); ++m) {
          auto md = member_decorations.find({id, m});
          uint32_t off = 0, ms = 0;
          if (md != member_decorations.end()) {
            if (md->second.count(Offset)) off = md->second.at(Offset);
            if (md->second.count(MatrixStride)) ms = md->second.at(MatrixStride);
          }
          size = std::max(size, off + size_of(t.args[m], ms));
        }
        return size;
      }
      default:
        return 0;
    }
  }

  VkDescriptorType descriptor_type(uint32_t type_id, uint32_t storage, uint32_t& count) const {
    count = 1;
    const Type* t = &type(type_id);
    while (t->op == OpTypeArray || t->op == OpTypeRuntimeArray) {
      if (t->op == OpTypeRuntimeArray) fail("%s: runtime-sized descriptor arrays are not supported", where.c_str());
      count *= uint32_t(constants.count(t->args[1]) ? constants.at(t->args[1]) : 1);
      type_id = t->args[0];
      t = &type(type_id);
    }
    switch (t->op) {
      case OpTypeSampler:
        return VK_DESCRIPTOR_TYPE_SAMPLER;
      case OpTypeSampledImage: {
        const Type& img = type(t->args[0]);
        return img.args[1] == 5 ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      }
      case OpTypeImage: {
        uint32_t dim = t->args[1], sampled = t->args[5];
        if (dim == 5)
          return sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        if (dim == 6) return VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT;
        return sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
      }
      case OpTypeStruct:
        if (storage == StorageBuffer || has(type_id, BufferBlock)) return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      case OpTypeAccelerationStructure:
        return VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
      default:
        fail("%s: unsupported descriptor declaration (SPIR-V op %u)", where.c_str(), t->op);
    }
  }
};

}  // namespace

ShaderReflection reflect_spirv(const std::vector<uint32_t>& code, const std::string& name) {
  if (code.size() < 5 || code[0] != 0x07230203u) fail("%s: not SPIR-V (bad magic)", name.c_str());
  Parser p;
  p.where = name;
  ShaderReflection out;
  struct Var {
    uint32_t id, type, storage;
  };
  std::vector<Var> vars;
  std::vector<uint32_t> local_size_ids;
  for (size_t i = 5; i < code.size();) {
    uint32_t words = code[i] >> 16, op = code[i] & 0xffff;
    if (words == 0 || i + words > code.size()) fail("%s: truncated SPIR-V at word %zu", name.c_str(), i);
    const uint32_t* w = &code[i];
    switch (op) {
      case OpName: {
        const char* s = reinterpret_cast<const char*>(w + 2);
        p.names[w[1]] = std::string(s, strnlen(s, (words - 2) * 4));
        break;
      }
      case OpExecutionMode:
        if (w[2] == 17 && words >= 6)
          out.local_size[0] = w[3], out.local_size[1] = w[4], out.local_size[2] = w[5];  // LocalSize
        break;
      case OpExecutionModeId:  // SPIR-V 1.6 (glslang for Vulkan 1.3): LocalSizeId with constant ids
        if (w[2] == 38 && words >= 6) local_size_ids = {w[3], w[4], w[5]};
        break;
      case OpDecorate:
        if (words >= 3) p.decorations[w[1]][w[2]] = words >= 4 ? w[3] : 1;
        break;
      case OpMemberDecorate:
        if (words >= 4) p.member_decorations[{w[1], w[2]}][w[3]] = words >= 5 ? w[4] : 1;
        break;
      case OpTypeBool:
      case OpTypeInt:
      case OpTypeFloat:
      case OpTypeVector:
      case OpTypeMatrix:
      case OpTypeImage:
      case OpTypeSampler:
      case OpTypeSampledImage:
      case OpTypeArray:
      case OpTypeRuntimeArray:
      case OpTypeStruct:
      case OpTypePointer:
      case OpTypeAccelerationStructure:
        p.types[w[1]] = Type{op, std::vector<uint32_t>(w + 2, w + words)};
        break;
      case OpConstant:
        if (words >= 4) p.constants[w[2]] = w[3];
        break;
      case OpVariable:
        vars.push_back({w[2], w[1], w[3]});
        break;
      default:
        break;
    }
    i += words;
  }
  for (size_t k = 0; k < local_size_ids.size(); ++k) {
    auto c = p.constants.find(local_size_ids[k]);
    if (c == p.constants.end())
      fail("%s: LocalSizeId refers to a non-constant (specialization constants are not supported)", name.c_str());
    out.local_size[k] = uint32_t(c->second);
  }
  for (const Var& v : vars) {
    if (v.storage != UniformConstant && v.storage != Uniform && v.storage != StorageBuffer && v.storage != PushConstant)
      continue;
    const Type& ptr = p.type(v.type);
    uint32_t pointee = ptr.args[1];
    if (v.storage == PushConstant) {
      out.push_constant_size = std::max<uint32_t>(out.push_constant_size, uint32_t(p.size_of(pointee, 0)));
      continue;
    }
    if (!p.has(v.id, Binding)) continue;
    ReflectedBinding b;
    b.set = p.get(v.id, DescriptorSet);
    b.binding = p.get(v.id, Binding);
    b.type = p.descriptor_type(pointee, v.storage, b.count);
    b.name = p.names.count(v.id) && !p.names[v.id].empty() ? p.names[v.id]
                                                           : (p.names.count(pointee) ? p.names[pointee] : "");
    out.bindings.push_back(b);
  }
  std::sort(out.bindings.begin(), out.bindings.end(),
            [](auto& a, auto& b) { return a.set != b.set ? a.set < b.set : a.binding < b.binding; });
  return out;
}

}  // namespace cumulo::gpu::detail
