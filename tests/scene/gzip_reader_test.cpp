/// Tests of the in-memory gzip reader behind pbrt's `.gz` files: exact round trips, concatenated
/// members, and hostile data (not gzip, corrupt, truncated, trailing bytes, a zip bomb).
#include "penumbra/scene/gzip_reader.h"

#include <zlib.h>

#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"

namespace penumbra {
namespace {

/// `data` as one gzip member (deflate with a gzip header and trailer).
std::string gzip(const std::string& data) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, uLong(data.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = uInt(data.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

/// The message gunzip throws for `bytes`, or "(no error)".
std::string error_of(const std::string& bytes, uint64_t max_bytes = 1 << 30) {
  try {
    gunzip(bytes, "m.ply.gz", max_bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Gunzip, RoundTripsExactlyAcrossBufferSizes) {
  std::string data;
  for (int i = 0; i < 3 << 20; ++i) data += char((i * 2654435761u) >> 24);  // 3 MiB, 3 buffers
  EXPECT_EQ(gunzip(gzip(data), "a.gz", 1 << 30), data);
  EXPECT_EQ(gunzip(gzip(""), "empty.gz", 1 << 30), "");
  // Concatenated members read as their concatenation (what `cat a.gz b.gz` gives).
  EXPECT_EQ(gunzip(gzip("ply\n") + gzip("format ascii 1.0\n"), "c.gz", 1 << 30),
            "ply\nformat ascii 1.0\n");
}

TEST(Gunzip, HostileDataIsRefusedAtItsByteOffset) {
  EXPECT_EQ(error_of(""), "m.ply.gz: empty file (0 bytes), not gzip data");
  EXPECT_EQ(error_of("ply\nformat"), "m.ply.gz:byte 0: not gzip data (no 1f 8b signature)");
  const std::string good = gzip(std::string(100000, 'a') + "b");
  // Cut short: no end of stream.
  const std::string cut = error_of(good.substr(0, good.size() / 2));
  EXPECT_NE(cut.find("gzip data ends too early (truncated)"), std::string::npos) << cut;
  // A flipped byte in the deflate data, or in the trailer's CRC.
  std::string bad = good;
  bad[12] ^= 0x55;
  EXPECT_NE(error_of(bad).find("m.ply.gz:byte "), std::string::npos) << error_of(bad);
  EXPECT_NE(error_of(bad).find("corrupt gzip data"), std::string::npos) << error_of(bad);
  std::string crc = good;
  crc[crc.size() - 6] ^= 1;
  EXPECT_NE(error_of(crc).find("corrupt gzip data: incorrect data check"), std::string::npos)
      << error_of(crc);
  // Bytes after the last member that are not another member.
  EXPECT_EQ(error_of(good + "junk"), "m.ply.gz:byte " + std::to_string(good.size()) +
                                         ": 4 bytes of trailing data after the gzip data");
}

TEST(Gunzip, AZipBombStopsAtTheBound) {
  // 64 MiB of zeros compress to about 64 KiB; the bound stops the inflation at 1 MiB.
  const std::string bomb = gzip(std::string(64 << 20, '\0'));
  ASSERT_LT(bomb.size(), 100000u);
  const std::string m = error_of(bomb, 1 << 20);
  EXPECT_EQ(m,
            "m.ply.gz: decompresses to more than 1.0 MiB (the memory limit; --max-memory "
            "changes it)");
  EXPECT_EQ(gunzip(bomb, "m.ply.gz", 64 << 20).size(), size_t(64) << 20);  // exactly at the bound
}

}  // namespace
}  // namespace penumbra
