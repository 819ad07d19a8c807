/// Writes the EXR seeds of fuzz/corpus/exr/: 4x3 images in each compression, half and float
/// channels, scanline and tiled, RGB and luminance-only. Build and run once:
///   g++ -std=c++20 make_exr_seeds.cpp $(pkg-config --cflags --libs OpenEXR) -o /tmp/exr_seeds
///   /tmp/exr_seeds fuzz/corpus/exr
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTiledOutputFile.h>

#include <string>
#include <vector>

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  const int w = 4, h = 3;
  std::vector<float> pixels(w * h * 3);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = 0.1f * static_cast<float>(i % 17);
  const struct {
    Imf::Compression c;
    const char* name;
  } kinds[] = {{Imf::NO_COMPRESSION, "none"},   {Imf::RLE_COMPRESSION, "rle"},
               {Imf::ZIPS_COMPRESSION, "zips"}, {Imf::ZIP_COMPRESSION, "zip"},
               {Imf::PIZ_COMPRESSION, "piz"},   {Imf::PXR24_COMPRESSION, "pxr24"},
               {Imf::B44_COMPRESSION, "b44"},   {Imf::DWAA_COMPRESSION, "dwaa"}};
  for (const auto& k : kinds) {
    for (const Imf::PixelType type : {Imf::HALF, Imf::FLOAT}) {
      for (const bool tiled : {false, true}) {
        const bool luminance = k.c == Imf::RLE_COMPRESSION && type == Imf::HALF;
        Imf::Header header(w, h);
        header.compression() = k.c;
        const char* names[3] = {"R", "G", "B"};
        const int channels = luminance ? 1 : 3;
        if (luminance) names[0] = "Y";
        std::vector<char> buffer(w * h * 3 * 4);
        Imf::FrameBuffer frame;
        for (int c = 0; c < channels; ++c) {
          header.channels().insert(names[c], Imf::Channel(type));
          const size_t size = type == Imf::HALF ? 2 : 4;
          frame.insert(names[c], Imf::Slice(type, buffer.data() + c * size, size * channels,
                                            size * channels * w));
        }
        const std::string path = dir + "/" + k.name + (type == Imf::HALF ? "-half" : "-float") +
                                 (tiled ? "-tiled" : "") + (luminance ? "-y" : "") + ".exr";
        if (tiled) {
          header.setTileDescription(Imf::TileDescription(2, 2, Imf::ONE_LEVEL));
          Imf::TiledOutputFile file(path.c_str(), header);
          file.setFrameBuffer(frame);
          file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
        } else {
          Imf::OutputFile file(path.c_str(), header);
          file.setFrameBuffer(frame);
          file.writePixels(h);
        }
      }
    }
  }
  return 0;
}
