#include "penumbra/scene/gzip_reader.h"

#include <zlib.h>

#include <algorithm>
#include <climits>

#include "penumbra/core/error.h"
#include "penumbra/core/input_file.h"
#include "penumbra/core/memory_limit.h"

namespace penumbra {
namespace {

// Ends the inflate stream when it goes out of scope.
struct Inflater {
  z_stream z{};
  bool open = false;
  ~Inflater() {
    if (open) inflateEnd(&z);
  }
};

std::string byte_place(uint64_t at) {
  return "byte " + std::to_string(at);
}

}  // namespace

std::string gunzip(std::string_view compressed, const std::string& name, uint64_t max_bytes) {
  if (compressed.empty()) throw InputError(name, "", "empty file (0 bytes), not gzip data");
  std::string out;
  uint64_t at = 0;  // where the current member starts in `compressed`
  while (at < compressed.size()) {
    const auto* begin = reinterpret_cast<const unsigned char*>(compressed.data()) + at;
    const uint64_t left = compressed.size() - at;
    if (left < 2 || begin[0] != 0x1f || begin[1] != 0x8b) {
      if (at == 0) throw InputError(name, byte_place(0), "not gzip data (no 1f 8b signature)");
      throw InputError(name, byte_place(at),
                       std::to_string(left) + " bytes of trailing data after the gzip data");
    }
    Inflater inf;
    if (inflateInit2(&inf.z, 16 + MAX_WBITS) != Z_OK)  // 16: a gzip header and trailer
      throw Error(name + ": cannot start zlib");
    inf.open = true;
    inf.z.next_in = const_cast<unsigned char*>(begin);
    inf.z.avail_in = uInt(std::min<uint64_t>(left, UINT_MAX));
    int rc = Z_OK;
    while (rc != Z_STREAM_END) {
      if (out.size() > max_bytes)
        throw InputError(name, "",
                         "decompresses to more than " + format_bytes(double(max_bytes)) +
                             " (the memory limit; --max-memory changes it)");
      // Room for one byte more than the bound: data of exactly max_bytes ends the stream in it.
      // The output doubles from 64 KiB up to 1 MiB steps, so a small file allocates little.
      const uint64_t step = std::clamp<uint64_t>(out.size(), 1 << 16, 1 << 20);
      const size_t grow = size_t(std::min<uint64_t>(max_bytes + 1 - out.size(), step));
      const size_t old = out.size();
      out.resize(old + grow);
      inf.z.next_out = reinterpret_cast<unsigned char*>(out.data() + old);
      inf.z.avail_out = uInt(grow);
      rc = inflate(&inf.z, Z_NO_FLUSH);
      out.resize(old + (grow - inf.z.avail_out));
      const uint64_t consumed = uint64_t(inf.z.next_in - begin);
      if (rc == Z_STREAM_END) break;
      if (rc == Z_BUF_ERROR && inf.z.avail_in == 0)
        throw InputError(name, byte_place(at + consumed), "gzip data ends too early (truncated)");
      if (rc != Z_OK) {
        const std::string why = inf.z.msg ? inf.z.msg : "invalid data";
        throw InputError(name, byte_place(at + consumed), "corrupt gzip data: " + why);
      }
      if (inf.z.avail_in == 0 && left > UINT_MAX) {  // members above 4 GiB: feed the rest
        const uint64_t rest = left - consumed;
        inf.z.avail_in = uInt(std::min<uint64_t>(rest, UINT_MAX));
      }
    }
    at += uint64_t(inf.z.next_in - begin);
  }
  return out;
}

std::string read_gzip_file(const std::string& path) {
  return gunzip(read_input_file(path), path, memory_limit());
}

}  // namespace penumbra
