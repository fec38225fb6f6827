// An int64 array for results of unknown size (the matches of a replay): anonymous memory that
// grows in place (mremap moves pages, never copies them), in transparent huge pages where the
// kernel allows them, and is handed to numpy without a copy. Ten million matches are 0.5 GB of
// arrays: with std::vector, the copies on growth and the 4 KiB page faults cost several times the
// detector's own time.
#pragma once

#include <pybind11/numpy.h>
#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <new>
#include <span>
#include <utility>
#include <vector>

namespace dw::python {

class GrowingArray {
 public:
  GrowingArray() = default;
  GrowingArray(const GrowingArray&) = delete;
  GrowingArray& operator=(const GrowingArray&) = delete;
  GrowingArray(GrowingArray&& o) noexcept
      : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)), bytes_(std::exchange(o.bytes_, 0)) {}
  ~GrowingArray() {
    if (data_) ::munmap(data_, bytes_);
  }

  size_t size() const { return size_; }
  void append(size_t count, int64_t value) {
    reserve(size_ + count);
    std::fill_n(data_ + size_, count, value);
    size_ += count;
  }
  template <class T>
  void append(std::span<const T> values) {
    reserve(size_ + values.size());
    std::copy(values.begin(), values.end(), data_ + size_);
    size_ += values.size();
  }
  void append(const std::vector<int64_t>& values) { append(std::span<const int64_t>(values)); }

  // A numpy array of `shape` (its elements: size()) that owns the memory from now on, read-only.
  pybind11::array_t<int64_t> to_numpy(std::vector<pybind11::ssize_t> shape) && {
    if (!data_) reserve(1);  // numpy wants an address even for no elements
    struct Mapping {
      void* at;
      size_t bytes;
    };
    auto* mapping = new Mapping{std::exchange(data_, nullptr), std::exchange(bytes_, 0)};
    pybind11::capsule owner(mapping, [](void* p) {
      auto* m = static_cast<Mapping*>(p);
      ::munmap(m->at, m->bytes);
      delete m;
    });
    size_ = 0;
    pybind11::array_t<int64_t> out(shape, static_cast<const int64_t*>(mapping->at), owner);
    out.attr("flags").attr("writeable") = false;
    return out;
  }

 private:
  static constexpr size_t kHugePage = size_t{2} << 20;

  void reserve(size_t elements) {
    const size_t wanted = elements * sizeof(int64_t);
    if (wanted <= bytes_) return;
    size_t bytes = std::max({wanted, bytes_ * 2, kHugePage});
    bytes = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* at = data_ ? ::mremap(data_, bytes_, bytes, MREMAP_MAYMOVE)
                     : ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (at == MAP_FAILED) throw std::bad_alloc();
    ::madvise(at, bytes, MADV_HUGEPAGE);  // a hint: without it, 4 KiB pages
    data_ = static_cast<int64_t*>(at);
    bytes_ = bytes;
  }

  int64_t* data_ = nullptr;
  size_t size_ = 0;
  size_t bytes_ = 0;
};

}  // namespace dw::python
