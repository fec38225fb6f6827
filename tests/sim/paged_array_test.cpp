// Per-module records in pages kept only where a record is not the default (sim/paged_array.h).
#include "sim/paged_array.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "sim/bodies.h"

namespace dw::sim {
namespace {

constexpr size_t kPage = PagedArray<Velocity>::kPage;

TEST(PagedArray, ReadsTheDefaultWhereNothingWasSetAndKeepsOnlyPagesWithOtherRecords) {
  PagedArray<Velocity> v;
  v.resize(100 * kPage);
  const size_t bare = v.bytes();
  EXPECT_EQ(v.size(), 100 * kPage);
  EXPECT_EQ(v[5], Velocity{});
  // Setting the default where no page is kept keeps none.
  for (size_t i = 0; i < v.size(); i += 7) v.set(i, {});
  EXPECT_EQ(v.bytes(), bare);
  v.set(3 * kPage + 1, {{1, 0, 0}, {}});
  v.set(3 * kPage + 2, {{0, 2, 0}, {}});
  EXPECT_EQ(v.bytes(), bare + kPage * sizeof(Velocity));
  EXPECT_EQ(v[3 * kPage + 1].linear[0], 1.0f);
  EXPECT_EQ(v[3 * kPage + 2].linear[1], 2.0f);
  EXPECT_EQ(v[3 * kPage], Velocity{});
  EXPECT_EQ(v[4 * kPage + 1], Velocity{});
  // Back to the default: the page stays, the record reads the default.
  v.set(3 * kPage + 1, {});
  EXPECT_EQ(v[3 * kPage + 1], Velocity{});
}

TEST(PagedArray, EqualityIsOfTheRecordsHoweverTheyArePaged) {
  PagedArray<Pose> a, b;
  a.resize(3 * kPage);
  b.resize(3 * kPage);
  a.set(kPage + 4, Pose{{1, 2, 3}, {0, 0, 0, 1}});
  a.set(kPage + 4, Pose{});  // a page kept, holding only the default
  EXPECT_EQ(a, b);
  b.set(2 * kPage, Pose{{0, 0, 1}, {0, 0, 0, 1}});
  EXPECT_NE(a, b);
  PagedArray<Pose> copy = b;
  EXPECT_EQ(copy, b);
  copy.set(2 * kPage, Pose{});
  EXPECT_NE(copy, b);  // a copy has pages of its own
  EXPECT_EQ(b[2 * kPage].position[2], 1.0f);
  PagedArray<Pose> shorter;
  shorter.resize(3 * kPage - 1);
  EXPECT_NE(shorter, a);
}

TEST(PagedArray, ShrinkingForgetsTheRecordsCutOff) {
  PagedArray<Velocity> v;
  v.resize(2 * kPage);
  v.set(kPage + 10, {{1, 1, 1}, {}});
  v.set(kPage + 2, {{2, 2, 2}, {}});
  v.resize(kPage + 5);
  v.resize(2 * kPage);
  EXPECT_EQ(v[kPage + 10], Velocity{});
  EXPECT_EQ(v[kPage + 2].linear[0], 2.0f);
}

TEST(PagedArray, WrittenAndReadBackGivesTheSameRecords) {
  PagedArray<Pose> a;
  a.resize(5 * kPage + 17);
  a.set(1, Pose{{1, 0, 0}, {0, 0, 0, 1}});
  a.set(5 * kPage + 16, Pose{{0, 0, 7}, {0, 0, 1, 0}});
  std::vector<std::byte> bytes;
  a.write([&](const void* data, size_t n) {
    const auto* p = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), p, p + n);
  });
  EXPECT_EQ(bytes.size(), a.written_bytes());
  EXPECT_EQ(bytes.size(), sizeof(uint64_t) + 6 + 2 * kPage * sizeof(Pose));  // two of six pages kept
  size_t at = 0;
  const auto take = [&](void* into, size_t n) {
    if (n > bytes.size() - at) throw std::logic_error("past the end");
    std::memcpy(into, bytes.data() + at, n);
    at += n;
  };
  PagedArray<Pose> b;
  b.read(take, bytes.size());
  EXPECT_EQ(at, bytes.size());
  EXPECT_EQ(b, a);
  EXPECT_EQ(b.bytes(), a.bytes());

  // A size whose page flags could not be there is refused before anything is allocated for it.
  const uint64_t huge = uint64_t{1} << 60;
  std::memcpy(bytes.data(), &huge, sizeof huge);
  at = 0;
  EXPECT_THROW(b.read(take, bytes.size()), std::logic_error);
}

// Poses whose default is each module's cell: a lattice at rest keeps none, and the cells come
// back with the records read from bytes.
TEST(PagedArray, PerIndexDefaultsAreEachModulesCellAndTravelWithTheRecords) {
  const LatticeSpec spec{LatticeKind::Fcc, {7, 5, 9}};
  PagedArray<Pose, CellPose> poses(CellPose{spec, 1});
  poses.resize(spec.module_count());
  const size_t bare = poses.bytes();
  for (ModuleId m = 0; m < poses.size(); ++m) {
    ASSERT_EQ(poses[m].position, cell_position(spec, m));
    poses.set(m, poses[m]);  // at rest where it is: nothing kept
  }
  EXPECT_EQ(poses.bytes(), bare);
  const ModuleId moved = 300;
  const Pose away{{-3, 2, 1}, {0, 0, 1, 0}};
  poses.set(moved, away);
  EXPECT_EQ(poses.bytes(), bare + kPage * sizeof(Pose));
  // The others of its page keep their cells.
  EXPECT_EQ(poses[moved + 1].position, cell_position(spec, moved + 1));
  EXPECT_EQ(poses[moved - 1].position, cell_position(spec, moved - 1));

  std::vector<std::byte> bytes;
  poses.write([&](const void* data, size_t n) {
    const auto* p = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), p, p + n);
  });
  size_t at = 0;
  PagedArray<Pose, CellPose> read;  // no lattice: every default at the origin
  EXPECT_NE(read, poses);
  read.read(
      [&](void* into, size_t n) {
        std::memcpy(into, bytes.data() + at, n);
        at += n;
      },
      bytes.size());
  EXPECT_EQ(read, poses);
  EXPECT_EQ(read.defaults(), poses.defaults());
  EXPECT_EQ(read[moved], away);
  EXPECT_EQ(read[5].position, cell_position(spec, 5));
}

}  // namespace
}  // namespace dw::sim
