// Forging .surfels files whose checksums are right but whose values are not, to test what the reader
// does with values pbs never writes.
#pragma once

#include <pbs/raster/hash64.hpp>

// The private layout: the forger must know where a record's values lie.
#include "../surfels/src/surfel_file_layout.hpp"

#include <cstring>
#include <span>
#include <string>

namespace pbs::stability {

// The doubles of an array record, in layout order (see layoutArray).
enum class ArrayField : std::size_t { BoxMinX = 0, BoxMaxZ = 5, Coverage = 6, Packing = 7, Area = 8 };

// Sets `field` of array `array` in the file's `bytes` to `value` and re-seals the array table.
inline void forgeArrayValue(std::string& bytes, std::uint32_t array, ArrayField field, double value) {
  using namespace surfel_file;
  Header header;
  ByteSource source{std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), kHeaderBytes)};
  layoutHeader(source, header);
  const std::size_t table = header.arrayTableOffset;
  const std::size_t recordBytes = arrayRecordBytes(header.version);
  const std::size_t tableBytes = std::size_t(header.arrayCount) * recordBytes;
  const std::size_t at = table + array * recordBytes + std::size_t(field) * sizeof(double);
  std::memcpy(bytes.data() + at, &value, sizeof value);
  const std::uint64_t checksum = Hash64::of(bytes.data() + table, tableBytes, kArrayTableSeed);
  std::memcpy(bytes.data() + table + tableBytes, &checksum, sizeof checksum);
}

}  // namespace pbs::stability
