#include "modules/clouds/reference/exr_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <exception>
#include <system_error>

#include "engine/core/error.h"

namespace cumulo::clouds {

void write_exr(const std::filesystem::path& path, uint32_t width, uint32_t height, const std::vector<glm::vec4>& rgba) {
  if (width == 0 || height == 0 || rgba.size() != size_t(width) * height)
    fail("%s: %ux%u image with %zu pixels", path.string().c_str(), width, height, rgba.size());
  namespace fs = std::filesystem;
  const fs::path tmp = path.string() + ".tmp";
  try {
    Imf::Header header{int(width), int(height)};
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[4] = {"R", "G", "B", "A"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(tmp.string().c_str(), header);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 4; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(reinterpret_cast<const float*>(rgba.data()) + c), sizeof(glm::vec4),
                                     sizeof(glm::vec4) * width));
    file.setFrameBuffer(fb);
    file.writePixels(int(height));
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    fail("%s: cannot write the EXR image: %s", path.string().c_str(), e.what());
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    fail("%s: cannot write the EXR image: %s", path.string().c_str(), ec.message().c_str());
  }
}

std::vector<glm::vec4> read_exr(const std::filesystem::path& path, uint32_t* width, uint32_t* height) {
  try {
    Imf::InputFile file(path.string().c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > 65536 || h > 65536) fail("%s: %dx%d data window", path.string().c_str(), w, h);
    for (const char* n : {"R", "G", "B"})
      if (!file.header().channels().findChannel(n)) fail("%s: no %s channel", path.string().c_str(), n);
    std::vector<glm::vec4> px(size_t(w) * size_t(h), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    float* base = reinterpret_cast<float*>(px.data()) - (size_t(dw.min.y) * size_t(w) + size_t(dw.min.x)) * 4;
    for (int c = 0; c < 4; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(base + c), sizeof(glm::vec4), sizeof(glm::vec4) * size_t(w), 1, 1,
                                     c == 3 ? 1.0 : 0.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    *width = uint32_t(w), *height = uint32_t(h);
    return px;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail("%s: cannot read the EXR image: %s", path.string().c_str(), e.what());
  }
}

}  // namespace cumulo::clouds
