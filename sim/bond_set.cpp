#include "sim/bond_set.h"

#include "sim/sorted_vector.h"

namespace dw::sim {

void BondSet::insert(std::span<const Bond> sorted) {
  std::vector<Bond> more;
  for (const Bond& x : sorted)
    if (bit(x)) insert(x);
    else if (!std::binary_search(listed_.begin(), listed_.end(), x)) more.push_back(x);
  merge_into<Bond>(listed_, more);
}

void BondSet::erase(std::span<const Bond> sorted) {
  std::vector<Bond> gone;
  for (const Bond& x : sorted)
    if (bit(x)) erase(x);
    else gone.push_back(x);
  erase_from<Bond>(listed_, gone);
}

}  // namespace dw::sim
