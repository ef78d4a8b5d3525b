// Private to the scene library: a file's bytes mapped read-only into memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <utility>

namespace pbs {

// The kernel pages the file in as its bytes are touched, with no zero-filled buffer to read them into
// first, and may drop the pages again under memory pressure: a 2 GB scene file costs no 2 GB of
// anonymous memory while it is imported. Throws InputError naming the file when it cannot be opened.
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& file);
  ~MappedFile();
  MappedFile(MappedFile&& other) noexcept : data_(std::exchange(other.data_, nullptr)), size_(other.size_) {}
  MappedFile& operator=(MappedFile other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    return *this;
  }

  std::span<const std::uint8_t> bytes() const { return {static_cast<const std::uint8_t*>(data_), size_}; }

  // Lets the pages that hold the part of `range` within this mapping go from the process's memory (they
  // stay in the page cache, and are read again if touched): what a mesh decoded from the file no longer
  // needs. Whole pages, so a neighbour's bytes may have to be read again too; nothing changes for readers,
  // the mapping being read-only. Ranges outside the mapping are ignored.
  void releasePages(std::span<const std::uint8_t> range) const;

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace pbs
