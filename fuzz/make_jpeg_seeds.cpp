/// Writes the JPEG seeds of fuzz/corpus/jpeg/: 8x8 and 17x9 images, baseline and progressive,
/// colour (4:4:4 and 4:2:0) and greyscale, with and without restart markers, optimised Huffman
/// tables. Build and run once:
///   g++ -std=c++20 make_jpeg_seeds.cpp -ljpeg -o /tmp/jpeg_seeds && /tmp/jpeg_seeds
///   fuzz/corpus/jpeg
#include <cstdio>
#include <cstdlib>

#include <jpeglib.h>

#include <string>
#include <vector>

namespace {

void write(const std::string& path, int w, int h, bool grey, bool progressive, bool subsample,
           int restart, bool optimize, int quality) {
  jpeg_compress_struct c{};
  jpeg_error_mgr err{};
  c.err = jpeg_std_error(&err);
  jpeg_create_compress(&c);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&c, &out, &size);
  c.image_width = w;
  c.image_height = h;
  c.input_components = grey ? 1 : 3;
  c.in_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  if (!subsample && !grey)
    for (int i = 0; i < 3; ++i) c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
  if (progressive) jpeg_simple_progression(&c);
  c.restart_interval = restart;
  c.optimize_coding = optimize;
  jpeg_start_compress(&c, TRUE);
  std::vector<unsigned char> row(size_t(w) * c.input_components);
  for (int y = 0; y < h; ++y) {
    for (size_t i = 0; i < row.size(); ++i)
      row[i] = static_cast<unsigned char>((i * 37 + y * 91) & 255);
    unsigned char* p = row.data();
    jpeg_write_scanlines(&c, &p, 1);
  }
  jpeg_finish_compress(&c);
  jpeg_destroy_compress(&c);
  FILE* f = std::fopen(path.c_str(), "wb");
  std::fwrite(out, 1, size, f);
  std::fclose(f);
  std::free(out);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = std::string(argc > 1 ? argv[1] : ".") + "/";
  write(dir + "baseline-444.jpg", 8, 8, false, false, false, 0, false, 95);
  write(dir + "baseline-420-17x9.jpg", 17, 9, false, false, true, 0, false, 75);
  write(dir + "grey.jpg", 8, 8, true, false, false, 0, false, 90);
  write(dir + "progressive.jpg", 17, 9, false, true, true, 0, false, 80);
  write(dir + "progressive-grey.jpg", 8, 8, true, true, false, 0, false, 80);
  write(dir + "restart-optimized.jpg", 17, 9, false, false, true, 1, true, 60);
  return 0;
}
