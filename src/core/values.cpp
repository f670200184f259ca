#include "slamkit/core/values.h"

#include <algorithm>

namespace slamkit {

std::size_t Values::num_fixed() const {
  return std::count_if(vars_.begin(), vars_.end(), [](const Variable& v) { return v.fixed; });
}

std::size_t Values::index_of(Key key) const {
  if (index_) {
    const auto it = index_->find(key);
    if (it != index_->end()) return it->second;
  }
  throw InputError("", 0, "key", "no variable " + key_to_string(key));
}

}  // namespace slamkit
