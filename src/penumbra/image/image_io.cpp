/// Format dispatch by extension and atomic (write-then-rename) file replacement.
#include "penumbra/image/image_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "penumbra/core/output_file.h"
#include "penumbra/image/exr.h"
#include "penumbra/image/jpeg.h"
#include "penumbra/image/pfm.h"
#include "penumbra/image/png.h"

namespace penumbra {
namespace {

// The extension of path in lower case, with its dot.
std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// A name beside path that no other process or concurrent write uses.
std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

}  // namespace

void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::exists(dir, ec))
    throw Error(path + ": cannot write: directory '" + dir.string() + "' does not exist");
  if (!fs::is_directory(dir, ec))
    throw Error(path + ": cannot write: '" + dir.string() + "' is not a directory");
  // What is there already: only a regular file penumbra may write is replaced. A device, FIFO
  // or socket (a link to /dev/full, say) would be replaced by the rename, not written to.
  const std::string kind = special_file_kind(path);
  if (!kind.empty()) throw Error(path + ": cannot write: it is " + kind + ", not a regular file");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && (st.st_mode & 0222) == 0)
    throw Error(path + ": cannot write: the file exists and is read-only (not replaced)");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error(path + ": cannot write: directory '" + dir.string() + "' is not writable");
}

ImageFormat image_format_for(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return ImageFormat::kPng;
  if (ext == ".exr") return ImageFormat::kExr;
  if (ext == ".pfm") return ImageFormat::kPfm;
  throw Error(path + ": unknown image extension '" + ext + "' (valid: .exr, .pfm, .png)");
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write) {
  check_writable(path);  // again: the render may have run for hours since the first check
  const std::string temp = temp_path_for(path);
  std::error_code ignored;
  // Write the temporary file; an Error naming it is re-thrown naming path instead.
  try {
    write(temp);
  } catch (const Error& e) {
    std::filesystem::remove(temp, ignored);
    std::string message = e.what();
    for (std::size_t at = message.find(temp); at != message.npos; at = message.find(temp, at)) {
      message.replace(at, temp.size(), path);
      at += path.size();
    }
    throw Error(message);
  } catch (...) {
    std::filesystem::remove(temp, ignored);
    throw;
  }
  // Replace path in one step.
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::filesystem::remove(temp, ignored);
    throw Error(path + ": cannot replace with the finished file: " + error.message());
  }
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_atomically(path, [&](const std::string& temp) { write_output_file(temp, bytes); });
}

void write_image(const RgbImage& image, const std::string& path) {
  const ImageFormat format = image_format_for(path);
  write_atomically(path, [&](const std::string& temp) {
    switch (format) {
      case ImageFormat::kPng:
        write_png(image, temp);
        break;
      case ImageFormat::kExr:
        write_exr(image, temp);
        break;
      case ImageFormat::kPfm:
        write_pfm(image, temp);
        break;
    }
  });
}

RgbImage read_image(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".jpg" || ext == ".jpeg") return read_jpeg(path);
  switch (image_format_for(path)) {
    case ImageFormat::kPng:
      return read_png(path);
    case ImageFormat::kExr:
      return read_exr(path);
    case ImageFormat::kPfm:
      return read_pfm(path);
  }
  throw Error(path + ": unknown image format");
}

RgbImage decode_image(std::string_view bytes, const std::string& name, std::size_t max_pixels) {
  if (bytes.starts_with("\x89PNG")) return decode_png(bytes, name, max_pixels);
  if (bytes.starts_with("\xFF\xD8")) return decode_jpeg(bytes, name, max_pixels);
  throw InputError(name, "byte 0", "neither a PNG nor a JPEG file (unknown signature)");
}

}  // namespace penumbra
