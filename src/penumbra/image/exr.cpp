/// EXR reading and writing with OpenEXR's general InputFile/OutputFile frame-buffer interface.
#include "penumbra/image/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cstdint>
#include <exception>

namespace penumbra {
namespace {

static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb must be three packed floats");

// Describes one float channel of image's pixels (channel 0, 1, 2 = r, g, b) to OpenEXR.
Imf::Slice rgb_slice(const Rgb* pixels, int channel, const Imath::Box2i& window) {
  const char* base = reinterpret_cast<const char*>(pixels) + channel * sizeof(float);
  return Imf::Slice::Make(Imf::FLOAT, base, window, sizeof(Rgb),
                          sizeof(Rgb) * static_cast<std::size_t>(window.max.x - window.min.x + 1));
}

}  // namespace

void write_exr(const RgbImage& image, const std::string& path) {
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  try {
    Imf::Header header(image.width(), image.height());
    header.compression() = Imf::ZIP_COMPRESSION;
    static constexpr const char* kNames[3] = {"R", "G", "B"};
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c) {
      header.channels().insert(kNames[c], Imf::Channel(Imf::FLOAT));
      frame.insert(kNames[c], rgb_slice(image.data(), c, header.dataWindow()));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height());
  } catch (const std::exception& e) {
    throw Error(path + ": cannot write EXR: " + e.what());
  }
}

RgbImage read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1;
    const std::int64_t height = std::int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0 || static_cast<std::uint64_t>(width * height) > kMaxImagePixels) {
      throw InputError(path, "",
                       "data window of " + std::to_string(width) + " x " + std::to_string(height) +
                           " pixels is empty or too large");
    }

    // Choose the source channel for r, g, b: R/G/B, or Y for all three.
    const Imf::ChannelList& channels = file.header().channels();
    const bool has_rgb =
        channels.findChannel("R") || channels.findChannel("G") || channels.findChannel("B");
    if (!has_rgb && !channels.findChannel("Y")) {
      throw InputError(path, "", "no R, G, B or Y channel");
    }
    static constexpr const char* kRgb[3] = {"R", "G", "B"};

    RgbImage image(static_cast<int>(width), static_cast<int>(height));
    Imf::FrameBuffer frame;
    frame.insert(has_rgb ? kRgb[0] : "Y", rgb_slice(image.data(), 0, window));
    if (has_rgb) {
      frame.insert(kRgb[1], rgb_slice(image.data(), 1, window));
      frame.insert(kRgb[2], rgb_slice(image.data(), 2, window));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (!has_rgb) {
      for (std::size_t i = 0; i < image.size(); ++i) image.data()[i] = Rgb(image.data()[i].r);
    }
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace penumbra
