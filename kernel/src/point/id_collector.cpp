#include "point/id_collector.hpp"

#include <algorithm>

namespace sphray::detail {

bool IdCollector::add(std::uint32_t id) {
  ++total;
  if (first_only) return true;
  if (size < capacity) {
    ids[size++] = id;
    std::push_heap(ids, ids + size);
  } else if (capacity > 0 && id < ids[0]) {
    std::pop_heap(ids, ids + size);
    ids[size - 1] = id;
    std::push_heap(ids, ids + size);
  }
  return false;
}

void IdCollector::finish() {
  std::sort_heap(ids, ids + size);
}

void append_pair(std::vector<IdPair>& out, std::uint32_t first, std::uint32_t second) {
  out.push_back({first, second});
}

}  // namespace sphray::detail
