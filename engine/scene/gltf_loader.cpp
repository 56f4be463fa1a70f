// glTF 2.0 -> scene::Model. The only translation unit that compiles tinygltf and stb_image.
//
// [index]  third-party implementations  |  file-system and image callbacks  |  accessor reading
//          |  primitives  |  materials and textures  |  node hierarchy  |  public entry points
#include "engine/scene/gltf.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <unordered_set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "engine/core/log.h"
#include "engine/core/message.h"
#include "engine/core/number.h"

// ---- third-party implementations --------------------------------------------------------------------
// stb_image is compiled here with static linkage so that no other library's copy (cumulo_core owns
// stb_image_write) can clash at link time. tinygltf gets our own image loader and file callbacks.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#ifndef __clang__
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_FAILURE_USERMSG
#define STBI_MAX_DIMENSIONS 16384  // refuses absurd headers before allocating (a 16k RGBA8 texture is 1 GiB)
#include <stb/stb_image.h>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace cumulo::scene {

Bounds Bounds::transformed(const glm::mat4& m) const {
  Bounds out;
  if (empty()) return out;
  for (int i = 0; i < 8; ++i) {
    glm::vec3 c((i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z);
    out.add(glm::vec3(m * glm::vec4(c, 1.0f)));
  }
  return out;
}

size_t Model::vertex_count() const {
  size_t n = 0;
  for (auto& m : meshes) n += m.vertices.size();
  return n;
}

size_t Model::triangle_count() const {
  size_t n = 0;
  for (auto& m : meshes) n += m.indices.size() / 3;
  return n;
}

std::vector<const MeshInstance*> Model::instances_with_material(const std::string& name) const {
  std::vector<const MeshInstance*> out;
  for (auto& inst : instances) {
    int mat = meshes[inst.mesh].material;
    if (mat >= 0 && materials[size_t(mat)].name == name) out.push_back(&inst);
  }
  return out;
}

void generate_normals(std::span<Vertex> vertices, std::span<const uint32_t> indices) {
  for (auto& v : vertices) v.normal = glm::vec3(0.0f);
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    Vertex& a = vertices[indices[t]];
    Vertex& b = vertices[indices[t + 1]];
    Vertex& c = vertices[indices[t + 2]];
    // The unnormalized cross product weights each face by its area.
    glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
    a.normal += n;
    b.normal += n;
    c.normal += n;
  }
  for (auto& v : vertices) {
    float len = glm::length(v.normal);
    v.normal = len > 1e-20f ? v.normal / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

namespace {

// ---- file-system and image callbacks ----------------------------------------------------------------
// Our own callbacks: no path expansion, and external files can be refused altogether (fuzzing).
struct FsContext {
  bool allow_external = true;
};

bool fs_exists(const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  std::error_code ec;
  return ctx->allow_external && std::filesystem::is_regular_file(path, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  if (!ctx->allow_external) {
    if (err) *err += "external file " + quote(path) + " refused (no base directory)\n";
    return false;
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    if (err) *err += "cannot open external file " + quote(path) + "\n";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  return true;
}

bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

// Every image becomes RGBA8, whatever its source format (16-bit PNGs are reduced by stb_image).
bool decode_rgba8(tinygltf::Image* image, int index, const unsigned char* bytes, size_t size, std::string* err) {
  if (size > size_t(std::numeric_limits<int>::max())) {
    if (err) *err += strf("images[%d]: %zu bytes is too large\n", index, size);
    return false;
  }
  int w = 0, h = 0, comp = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &comp, 4);
  if (!pixels) {
    if (err) *err += strf("images[%d] (%s): cannot decode: %s\n", index, quote(image->uri).c_str(), stbi_failure_reason());
    return false;
  }
  image->width = w;
  image->height = h;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(pixels, pixels + size_t(w) * size_t(h) * 4);
  stbi_image_free(pixels);
  return true;
}

// tinygltf's image callback. Images stored in a bufferView are decoded later, by decode_buffer_images():
// tinygltf 2.7 hands over bufferView.byteOffset/byteLength without checking them against the buffer
// (a fuzzer found the out-of-bounds read), so we check the range ourselves first.
bool decode_image(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  return decode_rgba8(image, index, bytes, size_t(std::max(size, 0)), err);
}

// ---- accessor reading -------------------------------------------------------------------------------
class Reader {
 public:
  static constexpr size_t kMaxZeroElements = size_t(1) << 24;

  Reader(const tinygltf::Model& g, std::string file) : g_(g), file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& msg) const {
    throw Error(file_ + ": " + where + ": " + msg);
  }

  // A glTF number (tinygltf keeps doubles) narrowed to the float we store, by core/number.h's rule.
  float to_float(double v, const std::string& where) const {
    return narrow_number<float>(v, [&](const std::string& why) { fail(where, why); });
  }

  const tinygltf::Accessor& accessor(int index, const std::string& where) const {
    if (index < 0 || size_t(index) >= g_.accessors.size())
      fail(where, strf("accessor index %d out of range (%zu accessors)", index, g_.accessors.size()));
    return g_.accessors[size_t(index)];
  }

  // Reads `accessor` as `out_components` floats per element. Normalized integer types are mapped to
  // [0,1] / [-1,1] as the glTF spec (3.11) says; non-normalized integers are converted as they are.
  std::vector<float> floats(int index, int out_components, const std::string& where) const {
    const auto& acc = accessor(index, where);
    std::string here = strf("accessors[%d]", index);
    int comps = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (comps != out_components)
      fail(here, strf("expected %d components per element, got %d", out_components, comps));
    if (acc.bufferView < 0) {  // glTF: no bufferView means all zeros (unless sparse)
      if (acc.sparse.isSparse) fail(here, "sparse accessors are not supported");
      if (acc.count > kMaxZeroElements) fail(here, strf("count %zu without a bufferView is implausible", acc.count));
      return std::vector<float>(acc.count * size_t(comps), 0.0f);
    }
    const uint8_t* base = element_base(acc, index);  // validates the range before anything is allocated
    std::vector<float> out(acc.count * size_t(comps), 0.0f);
    size_t stride = element_stride(acc);
    for (size_t i = 0; i < acc.count; ++i) {
      const uint8_t* p = base + i * stride;
      for (int c = 0; c < comps; ++c) out[i * size_t(comps) + size_t(c)] = component(acc, p, c, here);
    }
    return out;
  }

  std::vector<uint32_t> indices(int index, size_t vertex_count, const std::string& where) const {
    const auto& acc = accessor(index, where);
    std::string here = strf("accessors[%d]", index);
    if (acc.type != TINYGLTF_TYPE_SCALAR) fail(here, "indices must be SCALAR");
    if (acc.bufferView < 0) fail(here, "indices without a bufferView");
    const uint8_t* base = element_base(acc, index);
    size_t stride = element_stride(acc);
    std::vector<uint32_t> out(acc.count);
    for (size_t i = 0; i < acc.count; ++i) {
      const uint8_t* p = base + i * stride;
      uint32_t v = 0;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); v = s; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&v, p, 4); break;
        default: fail(here, strf("index component type %d is not u8/u16/u32", acc.componentType));
      }
      if (v >= vertex_count) fail(here, strf("index %u at element %zu is out of range (%zu vertices)", v, i, vertex_count));
      out[i] = v;
    }
    return out;
  }

 private:
  size_t element_stride(const tinygltf::Accessor& acc) const {
    const auto& view = g_.bufferViews[size_t(acc.bufferView)];
    size_t packed = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType))) *
                    size_t(tinygltf::GetNumComponentsInType(uint32_t(acc.type)));
    return view.byteStride ? view.byteStride : packed;
  }

  // Validates the whole accessor range against its bufferView and buffer, then returns its first byte.
  const uint8_t* element_base(const tinygltf::Accessor& acc, int index) const {
    std::string here = strf("accessors[%d]", index);
    if (acc.sparse.isSparse) fail(here, "sparse accessors are not supported");
    if (acc.bufferView < 0 || size_t(acc.bufferView) >= g_.bufferViews.size())
      fail(here, strf("bufferView %d out of range (%zu bufferViews)", acc.bufferView, g_.bufferViews.size()));
    const auto& view = g_.bufferViews[size_t(acc.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= g_.buffers.size())
      fail(strf("bufferViews[%d]", acc.bufferView), strf("buffer %d out of range", view.buffer));
    const auto& buffer = g_.buffers[size_t(view.buffer)];
    int csize = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    int ncomp = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (csize <= 0 || ncomp <= 0) fail(here, "invalid componentType or type");
    size_t elem = size_t(csize) * size_t(ncomp);
    size_t stride = view.byteStride ? view.byteStride : elem;
    if (stride < elem) fail(here, strf("byteStride %zu is smaller than an element (%zu bytes)", stride, elem));
    if (acc.count == 0) return buffer.data.data();
    // Overflow-safe: every term is bounded by the buffer size before it is multiplied.
    if (acc.count > buffer.data.size()) fail(here, strf("count %zu exceeds the buffer size", acc.count));
    size_t end = acc.byteOffset + stride * (acc.count - 1) + elem;
    if (end > view.byteLength)
      fail(here, strf("reads bytes %zu..%zu past the end of bufferViews[%d] (%zu bytes)", acc.byteOffset, end,
                      acc.bufferView, view.byteLength));
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
      fail(strf("bufferViews[%d]", acc.bufferView),
           strf("range %zu+%zu exceeds buffers[%d] (%zu bytes)", view.byteOffset, view.byteLength, view.buffer,
                buffer.data.size()));
    return buffer.data.data() + view.byteOffset + acc.byteOffset;
  }

  float component(const tinygltf::Accessor& acc, const uint8_t* p, int c, const std::string& here) const {
    switch (acc.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p + 4 * c, 4); return f; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { float v = p[c]; return acc.normalized ? v / 255.0f : v; }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        float v = float(int8_t(p[c]));
        return acc.normalized ? std::max(v / 127.0f, -1.0f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s; std::memcpy(&s, p + 2 * c, 2);
        return acc.normalized ? float(s) / 65535.0f : float(s);
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t s; std::memcpy(&s, p + 2 * c, 2);
        return acc.normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s);
      }
      default: fail(here, strf("component type %d cannot be read as a vertex attribute", acc.componentType));
    }
  }

  const tinygltf::Model& g_;
  std::string file_;
};

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS: return "POINTS";
    case TINYGLTF_MODE_LINE: return "LINES";
    case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLES: return "TRIANGLES";
    case TINYGLTF_MODE_TRIANGLE_STRIP: return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN: return "TRIANGLE_FAN";
    default: return "unknown";
  }
}

// ---- primitives -------------------------------------------------------------------------------------
Mesh load_primitive(const Reader& r, const tinygltf::Model& g, size_t mesh_index, size_t prim_index) {
  const auto& gm = g.meshes[mesh_index];
  const auto& prim = gm.primitives[prim_index];
  std::string where = strf("meshes[%zu].primitives[%zu]", mesh_index, prim_index);
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      prim.mode != TINYGLTF_MODE_TRIANGLE_FAN)
    r.fail(where, strf("unsupported primitive mode %s (%d); only triangles are supported", mode_name(prim.mode), prim.mode));
  if (!prim.targets.empty()) LOG_WARN("%s: morph targets ignored", where.c_str());

  Mesh mesh;
  mesh.name = gm.primitives.size() > 1 ? strf("%s.%zu", gm.name.c_str(), prim_index) : gm.name;
  mesh.material = prim.material;
  if (prim.material >= int(g.materials.size()))
    r.fail(where, strf("material %d out of range (%zu materials)", prim.material, g.materials.size()));

  auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) r.fail(where, "has no POSITION attribute");
  std::vector<float> pos = r.floats(pos_it->second, 3, where + ".attributes.POSITION");
  size_t n = pos.size() / 3;
  mesh.vertices.resize(n);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 p(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      r.fail(where, strf("POSITION element %zu is not finite", i));
    mesh.vertices[i].position = p;
    mesh.vertices[i].normal = glm::vec3(0.0f, 1.0f, 0.0f);
    mesh.vertices[i].uv = glm::vec2(0.0f);
    mesh.bounds.add(p);
  }
  if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
    std::vector<float> uv = r.floats(it->second, 2, where + ".attributes.TEXCOORD_0");
    if (uv.size() / 2 != n) r.fail(where, strf("TEXCOORD_0 has %zu elements, POSITION has %zu", uv.size() / 2, n));
    for (size_t i = 0; i < n; ++i) mesh.vertices[i].uv = glm::vec2(uv[2 * i], uv[2 * i + 1]);
  }

  // Indices, then strips and fans unrolled into a triangle list with the spec's winding (3.7.2.1).
  std::vector<uint32_t> idx;
  if (prim.indices >= 0) {
    idx = r.indices(prim.indices, n, where + ".indices");
  } else {
    idx.resize(n);
    for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
  }
  if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
    if (idx.size() % 3 != 0) r.fail(where, strf("triangle list with %zu indices (not a multiple of 3)", idx.size()));
    mesh.indices = std::move(idx);
  } else if (idx.size() >= 3) {
    for (size_t i = 2; i < idx.size(); ++i) {
      if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        mesh.indices.insert(mesh.indices.end(), {idx[0], idx[i - 1], idx[i]});
      } else if (i % 2 == 0) {
        mesh.indices.insert(mesh.indices.end(), {idx[i - 2], idx[i - 1], idx[i]});
      } else {
        mesh.indices.insert(mesh.indices.end(), {idx[i - 1], idx[i - 2], idx[i]});
      }
    }
  }

  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    std::vector<float> nor = r.floats(it->second, 3, where + ".attributes.NORMAL");
    if (nor.size() / 3 != n) r.fail(where, strf("NORMAL has %zu elements, POSITION has %zu", nor.size() / 3, n));
    for (size_t i = 0; i < n; ++i) {
      glm::vec3 v(nor[3 * i], nor[3 * i + 1], nor[3 * i + 2]);
      float len = glm::length(v);
      mesh.vertices[i].normal = (std::isfinite(len) && len > 1e-20f) ? v / len : glm::vec3(0.0f, 1.0f, 0.0f);
    }
  } else {
    generate_normals(mesh.vertices, mesh.indices);
    mesh.generated_normals = true;
  }
  return mesh;
}

// ---- materials and textures -------------------------------------------------------------------------
Wrap to_wrap(int mode) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::MirroredRepeat;
    default: return Wrap::Repeat;
  }
}

Texture load_texture(const Reader& r, const tinygltf::Model& g, size_t index) {
  const auto& t = g.textures[index];
  std::string where = strf("textures[%zu]", index);
  if (t.source < 0 || size_t(t.source) >= g.images.size())
    r.fail(where, strf("source image %d out of range (%zu images)", t.source, g.images.size()));
  const auto& img = g.images[size_t(t.source)];
  Texture tex;
  tex.name = !t.name.empty() ? t.name : !img.name.empty() ? img.name : img.uri;
  if (img.image.empty())  // tinygltf reports a missing external image only as a warning
    r.fail(strf("images[%d]", t.source), strf("image %s could not be loaded (missing file or undecodable data)",
                                              quote(img.uri.empty() ? img.name : img.uri).c_str()));
  if (img.component != 4 || img.bits != 8 || img.width <= 0 || img.height <= 0 ||
      img.image.size() != size_t(img.width) * size_t(img.height) * 4)
    r.fail(strf("images[%d]", t.source), "image was not decoded to RGBA8");
  tex.width = uint32_t(img.width);
  tex.height = uint32_t(img.height);
  tex.rgba = img.image;
  if (t.sampler >= 0 && size_t(t.sampler) < g.samplers.size()) {
    const auto& s = g.samplers[size_t(t.sampler)];
    tex.wrap_u = to_wrap(s.wrapS);
    tex.wrap_v = to_wrap(s.wrapT);
    tex.linear_filter = s.magFilter != TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  return tex;
}

Material load_material(const Reader& r, const tinygltf::Model& g, size_t index) {
  const auto& m = g.materials[index];
  const auto& pbr = m.pbrMetallicRoughness;
  std::string where = strf("materials[%zu]", index);
  Material mat;
  mat.name = m.name;
  if (pbr.baseColorFactor.size() == 4)
    for (int i = 0; i < 4; ++i) mat.base_color_factor[i] = r.to_float(pbr.baseColorFactor[size_t(i)], where + ".baseColorFactor");
  if (pbr.baseColorTexture.index >= 0) {
    if (size_t(pbr.baseColorTexture.index) >= g.textures.size())
      r.fail(where, strf("baseColorTexture %d out of range (%zu textures)", pbr.baseColorTexture.index, g.textures.size()));
    mat.base_color_texture = pbr.baseColorTexture.index;
    if (pbr.baseColorTexture.texCoord != 0)
      LOG_WARN("%s: baseColorTexture uses TEXCOORD_%d; cumulo reads TEXCOORD_0", where.c_str(), pbr.baseColorTexture.texCoord);
  }
  mat.metallic = r.to_float(pbr.metallicFactor, where + ".metallicFactor");
  mat.roughness = r.to_float(pbr.roughnessFactor, where + ".roughnessFactor");
  if (m.emissiveFactor.size() == 3)
    for (int i = 0; i < 3; ++i) mat.emissive[i] = r.to_float(m.emissiveFactor[size_t(i)], where + ".emissiveFactor");
  mat.alpha_mode = m.alphaMode == "MASK" ? AlphaMode::Mask : m.alphaMode == "BLEND" ? AlphaMode::Blend : AlphaMode::Opaque;
  mat.alpha_cutoff = r.to_float(m.alphaCutoff, where + ".alphaCutoff");
  mat.double_sided = m.doubleSided;
  return mat;
}

// ---- node hierarchy ---------------------------------------------------------------------------------
glm::mat4 local_matrix(const Reader& r, const tinygltf::Node& n, const std::string& where) {
  auto f = [&](const std::vector<double>& v, size_t i, const char* what) { return r.to_float(v[i], where + "." + what); };
  if (n.matrix.size() == 16) {
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = f(n.matrix, size_t(i), "matrix");  // column-major, as glm
    return m;
  }
  glm::mat4 m(1.0f);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::vec3(f(n.translation, 0, "translation"), f(n.translation, 1, "translation"),
                                    f(n.translation, 2, "translation")));
  if (n.rotation.size() == 4)  // glTF stores x, y, z, w; glm's constructor takes w first
    m *= glm::mat4_cast(glm::quat(f(n.rotation, 3, "rotation"), f(n.rotation, 0, "rotation"), f(n.rotation, 1, "rotation"),
                                  f(n.rotation, 2, "rotation")));
  if (n.scale.size() == 3)
    m = glm::scale(m, glm::vec3(f(n.scale, 0, "scale"), f(n.scale, 1, "scale"), f(n.scale, 2, "scale")));
  return m;
}

void decode_buffer_images(const Reader& r, tinygltf::Model& g) {
  for (size_t i = 0; i < g.images.size(); ++i) {
    tinygltf::Image& img = g.images[i];
    if (img.bufferView < 0 || !img.image.empty()) continue;
    std::string where = strf("images[%zu]", i);
    if (size_t(img.bufferView) >= g.bufferViews.size()) r.fail(where, strf("bufferView %d out of range", img.bufferView));
    const auto& view = g.bufferViews[size_t(img.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= g.buffers.size())
      r.fail(strf("bufferViews[%d]", img.bufferView), strf("buffer %d out of range", view.buffer));
    const auto& buffer = g.buffers[size_t(view.buffer)];
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
      r.fail(strf("bufferViews[%d]", img.bufferView),
             strf("range %zu+%zu exceeds buffers[%d] (%zu bytes)", view.byteOffset, view.byteLength, view.buffer,
                  buffer.data.size()));
    std::string err;
    if (!decode_rgba8(&img, int(i), buffer.data.data() + view.byteOffset, view.byteLength, &err))
      r.fail(where, err.substr(0, err.find_last_not_of('\n') + 1));
  }
}

// Depth-first walk of the hierarchy under `roots`, calling visit(node, world matrix) in document order.
// Iterative, so a chain of 20,000 nodes cannot exhaust the stack. A node met again on its own path is
// a cycle; a node shared by several parents is visited once per path (glTF forbids sharing, but
// tinygltf does not check), and at most kMaxNodeVisits visits are made in all, because sharing at
// every level multiplies the paths to 2^depth.
constexpr size_t kMaxNodeVisits = size_t(1) << 20;

template <typename Visit>
void visit_nodes(const Reader& r, const tinygltf::Model& g, const std::vector<int>& roots, Visit&& visit) {
  // Each node's own matrix once (its numbers checked once), not once per path.
  std::vector<glm::mat4> local(g.nodes.size());
  for (size_t i = 0; i < g.nodes.size(); ++i) local[i] = local_matrix(r, g.nodes[i], strf("nodes[%zu]", i));
  struct Item {
    int index;
    bool leave;  // pops the node off the current path
    glm::mat4 parent;
  };
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, false, glm::mat4(1.0f)});
  std::vector<bool> on_path(g.nodes.size(), false);
  size_t visits = 0;
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (item.leave) {
      on_path[size_t(item.index)] = false;
      continue;
    }
    if (item.index < 0 || size_t(item.index) >= g.nodes.size())
      r.fail("nodes", strf("node index %d out of range (%zu nodes)", item.index, g.nodes.size()));
    if (on_path[size_t(item.index)]) r.fail(strf("nodes[%d]", item.index), "node hierarchy has a cycle");
    if (++visits > kMaxNodeVisits)
      r.fail(strf("nodes[%d]", item.index),
             strf("more than %zu node visits (nodes shared by several parents multiply)", kMaxNodeVisits));
    on_path[size_t(item.index)] = true;
    const glm::mat4 world = item.parent * local[size_t(item.index)];
    visit(item.index, world);
    stack.push_back({item.index, true, glm::mat4(1.0f)});
    const std::vector<int>& children = g.nodes[size_t(item.index)].children;
    for (auto c = children.rbegin(); c != children.rend(); ++c) stack.push_back({*c, false, world});
  }
}

Model convert(tinygltf::Model& g, const std::string& file) {
  Reader r(g, file);
  for (auto& ext : g.extensionsRequired) r.fail("extensionsRequired", "extension " + ext + " is not supported");
  Model model;
  model.source = file;

  decode_buffer_images(r, g);
  for (size_t i = 0; i < g.textures.size(); ++i) model.textures.push_back(load_texture(r, g, i));
  for (size_t i = 0; i < g.materials.size(); ++i) model.materials.push_back(load_material(r, g, i));
  // glTF 2.0 spec 3.9.2: base-color textures are sRGB; a texture used only elsewhere would be linear.
  std::vector<std::vector<uint32_t>> mesh_prims(g.meshes.size());
  for (size_t m = 0; m < g.meshes.size(); ++m) {
    for (size_t p = 0; p < g.meshes[m].primitives.size(); ++p) {
      mesh_prims[m].push_back(uint32_t(model.meshes.size()));
      model.meshes.push_back(load_primitive(r, g, m, p));
    }
  }

  // Flatten the default scene (or every root node when the file names no scene).
  std::vector<int> roots;
  if (!g.scenes.empty()) {
    int s = g.defaultScene >= 0 && size_t(g.defaultScene) < g.scenes.size() ? g.defaultScene : 0;
    roots = g.scenes[size_t(s)].nodes;
  } else {
    std::vector<bool> is_child(g.nodes.size(), false);
    for (auto& n : g.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < g.nodes.size()) is_child[size_t(c)] = true;
    for (size_t i = 0; i < g.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(int(i));
  }
  visit_nodes(r, g, roots, [&](int index, const glm::mat4& world) {
    const auto& n = g.nodes[size_t(index)];
    if (n.mesh < 0) return;
    if (size_t(n.mesh) >= g.meshes.size())
      r.fail(strf("nodes[%d]", index), strf("mesh %d out of range (%zu meshes)", n.mesh, g.meshes.size()));
    if (n.skin >= 0) LOG_WARN("%s: nodes[%d]: skin ignored (bind pose drawn)", file.c_str(), index);
    for (uint32_t mi : mesh_prims[size_t(n.mesh)]) {
      model.instances.push_back(MeshInstance{mi, world, n.name});
      model.bounds.add(model.meshes[mi].bounds.transformed(world));
    }
  });
  return model;
}

// The JSON text of a .gltf, or of a .glb's first chunk (glTF 2.0 spec 4.4: 12-byte header, then chunk
// length, type "JSON", data). Nothing for a malformed container: tinygltf refuses it with its own message.
std::optional<std::string_view> json_chunk(std::span<const uint8_t> bytes, bool binary) {
  const char* text = reinterpret_cast<const char*>(bytes.data());
  if (!binary) return std::string_view(text, bytes.size());
  if (bytes.size() < 20 || std::memcmp(bytes.data() + 16, "JSON", 4) != 0) return std::nullopt;
  uint32_t length;
  std::memcpy(&length, bytes.data() + 12, 4);
  return std::string_view(text + 20, std::min<size_t>(length, bytes.size() - 20));
}

}  // namespace

// ---- public entry points ----------------------------------------------------------------------------
Model load_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                            const std::filesystem::path& base_dir) {
  if (bytes.size() > 0xffffffffull) throw Error(name + ": file too large for glTF (over 4 GiB)");
  FsContext ctx{!base_dir.empty()};
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decode_image, nullptr);
  loader.SetFsCallbacks(tinygltf::FsCallbacks{fs_exists, fs_expand, fs_read, fs_write, &ctx});
  tinygltf::Model g;
  std::string err, warn;
  bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  // Our JSON rules first (depth limit, numbers that overflow): tinygltf converts JSON recursively and
  // would report an overflow as a raw library exception.
  if (auto json = json_chunk(bytes, binary)) check_json_text(*json, name);
  bool ok;
  try {  // tinygltf reports through err, but its JSON library may still throw on hostile input
    if (binary) {
      ok = loader.LoadBinaryFromMemory(&g, &err, &warn, bytes.data(), unsigned(bytes.size()), base_dir.string());
    } else {
      ok = loader.LoadASCIIFromString(&g, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                      unsigned(bytes.size()), base_dir.string());
    }
  } catch (const std::exception& e) {
    throw Error(name + ": glTF parse error: " + library_message(e.what()));
  }
  if (!ok) throw Error(name + ": glTF parse error: " + (err.empty() ? std::string("unknown error") : library_message(err)));
  if (!warn.empty()) LOG_WARN("%s: %s", name.c_str(), library_message(warn).c_str());
  return convert(g, name);
}

Model load_gltf(const std::filesystem::path& path) {
  std::vector<uint8_t> bytes = read_file_bytes(path);  // names the file and the OS reason on failure
  std::filesystem::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  return load_gltf_from_memory(bytes, path.string(), dir);
}

}  // namespace cumulo::scene
