#pragma once
// glTF 2.0 loading (.gltf with external or embedded buffers/images, and .glb) into a CPU Model.
//
// Supported: triangle lists/strips/fans (POINTS and LINES are refused), u8/u16/u32 indices (or none),
// POSITION, NORMAL (generated, area-weighted, when absent), TEXCOORD_0 (float or normalized u8/u16),
// base-color textures decoded to RGBA8 (PNG/JPEG/BMP/TGA/GIF via stb_image) and base-color factors,
// node hierarchies (matrix or TRS) flattened to world matrices of the default scene.
// Not supported: sparse accessors and any extension listed in extensionsRequired (Draco, meshopt, ...) are
// refused with a message; morph targets and skins are ignored with a warning (the bind pose is drawn).
//
// Every failure throws cumulo::Error naming the file: "FILE: cannot open ...", "FILE: glTF parse error:
// <tinygltf's text>", "FILE: meshes[2].primitives[0]: unsupported primitive mode LINES",
// "FILE: accessors[5]: reads bytes 0..4096 past the end of bufferViews[1] (2048 bytes)".
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "engine/scene/model.h"

namespace cumulo::scene {

// Loads a .gltf or .glb (chosen by the "glTF" magic, not the extension).
Model load_gltf(const std::filesystem::path& path);

// Same from bytes already in memory; `name` is used in error messages, `base_dir` resolves external URIs
// (pass an empty path to refuse external files, e.g. for fuzzing).
Model load_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                            const std::filesystem::path& base_dir);

// Area-weighted smooth vertex normals of an indexed triangle list (used when a file has no NORMAL).
void generate_normals(std::span<Vertex> vertices, std::span<const uint32_t> indices);

}  // namespace cumulo::scene
