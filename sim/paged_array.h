// Per-module records of which most hold their default (docs/design.md §8): the velocities of a
// lattice at rest are all zero, its modules' poses those of their cells, and the poses in their
// clusters' frames of modules in no moving cluster are never read. Records are kept in pages of
// 256, and a page is allocated only when a record in it is set to something else than its
// default: a still 100^3 lattice keeps none, where vectors would hold 80 MB.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace dw::sim {

// Every record's default: T{}.
template <typename T>
struct ValueDefault {
  T operator()(size_t) const { return T{}; }
  bool operator==(const ValueDefault&) const = default;
};

// `Default` gives each index's default record; it is copied and serialized bit for bit with the
// records (no padding), unless it is empty.
template <typename T, typename Default = ValueDefault<T>>
class PagedArray {
  static_assert(std::is_trivially_copyable_v<T>, "records are copied and serialized bit for bit");
  static_assert(std::is_trivially_copyable_v<Default>);

 public:
  static constexpr size_t kPage = 256;

  PagedArray() = default;
  explicit PagedArray(Default defaults) : default_(defaults) {}
  PagedArray(const PagedArray& other) : default_(other.default_), size_(other.size_), pages_(other.pages_.size()) {
    for (size_t p = 0; p < pages_.size(); ++p)
      if (other.pages_[p]) pages_[p] = std::make_unique<Page>(*other.pages_[p]);
  }
  PagedArray& operator=(const PagedArray& other) {
    if (this != &other) *this = PagedArray(other);
    return *this;
  }
  PagedArray(PagedArray&&) noexcept = default;
  PagedArray& operator=(PagedArray&&) noexcept = default;

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const Default& defaults() const { return default_; }
  // Records past the old size hold their default; those cut off are forgotten.
  void resize(size_t n) {
    pages_.resize((n + kPage - 1) / kPage);
    if (n < size_ && n % kPage != 0 && pages_.back())
      for (size_t i = n % kPage; i < kPage; ++i) (*pages_.back())[i] = default_(n - n % kPage + i);
    size_ = n;
  }

  // A copy, const so that writing to it does not compile (set() writes).
  const T operator[](size_t i) const {
    const std::unique_ptr<Page>& page = pages_[i / kPage];
    return page ? (*page)[i % kPage] : default_(i);
  }
  void set(size_t i, const T& value) {
    std::unique_ptr<Page>& page = pages_[i / kPage];
    if (!page) {
      if (value == default_(i)) return;
      page = std::make_unique<Page>();
      const size_t first = i - i % kPage;
      for (size_t k = 0; k < kPage; ++k) (*page)[k] = default_(first + k);
    }
    (*page)[i % kPage] = value;
  }

  // What its pages take on the heap (a pointer a page besides).
  size_t bytes() const {
    size_t n = pages_.capacity() * sizeof(pages_[0]);
    for (const auto& page : pages_)
      if (page) n += sizeof(Page);
    return n;
  }

  // Equal records, however they are paged or come by default.
  bool operator==(const PagedArray& other) const {
    if (size_ != other.size_) return false;
    for (size_t i = 0; i < size_; ++i)
      if (!((*this)[i] == other[i])) return false;
    return true;
  }

  // The records as bytes, a piece at a time, `lay(data, bytes)`: the defaults, the size, a byte
  // per page saying whether it is kept, and the kept pages. read() takes them back in that order from
  // `take(into, bytes)`, which must refuse to read past what it holds, of which `available` are
  // left.
  template <typename Lay>
  void write(Lay&& lay) const {
    if constexpr (!std::is_empty_v<Default>) lay(&default_, sizeof default_);
    const uint64_t n = size_;
    lay(&n, sizeof n);
    std::vector<uint8_t> kept(pages_.size());
    for (size_t p = 0; p < pages_.size(); ++p) kept[p] = pages_[p] ? 1 : 0;
    lay(kept.data(), kept.size());
    for (const auto& page : pages_)
      if (page) lay(page->data(), sizeof(Page));
  }
  template <typename Take>
  void read(Take&& take, uint64_t available) {
    Default defaults{};
    if constexpr (!std::is_empty_v<Default>) take(&defaults, sizeof defaults);
    uint64_t n = 0;
    take(&n, sizeof n);
    const uint64_t pages = n / kPage + (n % kPage != 0);
    if (pages > available) throw std::logic_error("paged records: more pages than bytes");
    std::vector<uint8_t> kept(pages);
    take(kept.data(), kept.size());
    PagedArray read(defaults);
    read.resize(n);
    for (size_t p = 0; p < kept.size(); ++p)
      if (kept[p]) {
        read.pages_[p] = std::make_unique<Page>();
        take(read.pages_[p]->data(), sizeof(Page));
      }
    *this = std::move(read);
  }
  // The bytes write() lays down.
  uint64_t written_bytes() const {
    uint64_t n = (std::is_empty_v<Default> ? 0 : sizeof(Default)) + sizeof(uint64_t) + pages_.size();
    for (const auto& page : pages_)
      if (page) n += sizeof(Page);
    return n;
  }

 private:
  using Page = std::array<T, kPage>;
  Default default_{};
  size_t size_ = 0;
  std::vector<std::unique_ptr<Page>> pages_;
};

}  // namespace dw::sim
