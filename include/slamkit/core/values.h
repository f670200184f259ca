// Values: the variables of an estimation problem, each a typed point on a manifold.
//
// Parameters of all variables live in one contiguous array (cache-friendly for the
// optimizer); each variable has a key, a manifold, an offset and a fixed flag. Typed
// access goes through ManifoldTraits<T>: insert<T>, at<T>, update<T>. Fixed variables
// keep their value (gauge, known calibration) and get no column in the linear system.
// Pointers returned by params() stay valid until the next insert().
// Not thread-safe for writes; concurrent reads are fine (also of copies: they share only the
// immutable key index).
#pragma once

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "slamkit/core/error.h"
#include "slamkit/core/key.h"
#include "slamkit/core/manifold.h"

namespace slamkit {

class Values {
 public:
  template <class T>
  void insert(Key key, const T& value) {
    const Manifold& m = ManifoldOf<T>::instance();
    if (!own_index().emplace(key, vars_.size()).second)
      throw InputError("", 0, "key", "variable " + key_to_string(key) + " inserted twice");
    vars_.push_back({key, &m, data_.size(), false});
    data_.resize(data_.size() + m.ambient_dim());
    ManifoldTraits<T>::to_params(value, data_.data() + vars_.back().offset);
  }

  template <class T>
  T at(Key key) const {
    const std::size_t i = checked_index<T>(key);
    return ManifoldTraits<T>::from_params(params(i));
  }

  template <class T>
  void update(Key key, const T& value) {
    ManifoldTraits<T>::to_params(value, params(checked_index<T>(key)));
  }

  /// Room for `variables` variables holding `params` parameters in all: inserting up to that
  /// many rehashes and regrows nothing.
  void reserve(std::size_t variables, std::size_t params) {
    vars_.reserve(variables);
    data_.reserve(params);
    own_index().reserve(variables);
  }

  bool exists(Key key) const { return index_ && index_->count(key) != 0; }
  std::size_t size() const { return vars_.size(); }
  void set_fixed(Key key, bool fixed = true) { vars_[index_of(key)].fixed = fixed; }
  bool is_fixed(Key key) const { return vars_[index_of(key)].fixed; }
  std::size_t num_fixed() const;

  // ---- low-level access by index (optimizer internals) ----
  std::size_t index_of(Key key) const;  ///< throws InputError if absent
  Key key(std::size_t i) const { return vars_[i].key; }
  const Manifold& manifold(std::size_t i) const { return *vars_[i].manifold; }
  bool fixed(std::size_t i) const { return vars_[i].fixed; }
  double* params(std::size_t i) { return data_.data() + vars_[i].offset; }
  const double* params(std::size_t i) const { return data_.data() + vars_[i].offset; }
  const std::vector<double>& parameter_data() const { return data_; }

 private:
  struct Variable {
    Key key;
    const Manifold* manifold;
    std::size_t offset;
    bool fixed;
  };

  template <class T>
  std::size_t checked_index(Key key) const {
    const std::size_t i = index_of(key);
    if (vars_[i].manifold != &ManifoldOf<T>::instance())
      throw InputError("", 0, "key", "variable " + key_to_string(key) + " is a " + vars_[i].manifold->name() +
                                         ", not a " + ManifoldOf<T>::instance().name());
    return i;
  }

  std::vector<Variable> vars_;
  std::vector<double> data_;
  // key → variable index. Copies share it until one of them inserts (copy on write): the
  // optimizer's candidate iterate is a copy, and copying a hash map is a heap node per key.
  using Index = std::unordered_map<Key, std::size_t>;
  std::shared_ptr<Index> index_ = std::make_shared<Index>();
  Index& own_index() {
    if (!index_) index_ = std::make_shared<Index>();  // moved from
    else if (index_.use_count() > 1) index_ = std::make_shared<Index>(*index_);
    return *index_;
  }
};

}  // namespace slamkit
