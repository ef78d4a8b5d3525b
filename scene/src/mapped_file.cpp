// mmap of a whole file, read-only and private; an empty file maps to no bytes (mmap refuses length 0).
#include "mapped_file.hpp"

#include "pbs/scene/input_error.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <string>

namespace pbs {

MappedFile::MappedFile(const std::filesystem::path& file) {
  const std::string name = file.string();
  const auto fail = [&](const char* what) { throw InputError(name, "", what + std::string(std::strerror(errno))); };
  const int descriptor = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0) fail("cannot open: ");
  // The mapping keeps the file; the descriptor is closed on every way out.
  const std::unique_ptr<const int, void (*)(const int*)> closing(&descriptor, [](const int* d) { ::close(*d); });
  struct stat status {};
  if (::fstat(descriptor, &status) != 0) fail("cannot read: ");
  if (!S_ISREG(status.st_mode)) {
    throw InputError(name, "", S_ISDIR(status.st_mode) ? "is a directory, not a file" : "is not a regular file");
  }
  size_ = static_cast<std::size_t>(status.st_size);
  if (size_ == 0) return;
  data_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, descriptor, 0);
  if (data_ == MAP_FAILED) {
    data_ = nullptr;
    fail("cannot map: ");
  }
}

void MappedFile::releasePages(std::span<const std::uint8_t> range) const {
  const auto begin = reinterpret_cast<std::uintptr_t>(data_);
  const std::uintptr_t first = std::max(reinterpret_cast<std::uintptr_t>(range.data()), begin);
  const std::uintptr_t last = std::min(reinterpret_cast<std::uintptr_t>(range.data()) + range.size(), begin + size_);
  if (!data_ || first >= last) return;
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t from = first / page * page;  // the mapping starts on a page: `from` is inside it
  // MADV_DONTNEED on a private mapping that was never written drops clean pages only: no data is lost.
  ::madvise(reinterpret_cast<void*>(from), last - from, MADV_DONTNEED);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(data_, size_);
}

}  // namespace pbs
