#include "slamkit/linear/sparse_cholesky.h"

#include <iostream>

#include "slamkit/core/error.h"
#include "sparse_cholesky_backends.h"

namespace slamkit {

const char* to_string(SparseBackend b) {
  switch (b) {
    case SparseBackend::kAuto: return "auto";
    case SparseBackend::kCholmod: return "cholmod";
    case SparseBackend::kEigen: return "eigen";
  }
  return "?";
}

const char* to_string(OrderingMethod m) {
  switch (m) {
    case OrderingMethod::kAuto: return "auto";
    case OrderingMethod::kAmd: return "amd";
    case OrderingMethod::kMetis: return "metis";
    case OrderingMethod::kNesdis: return "nesdis";
    case OrderingMethod::kNatural: return "natural";
  }
  return "?";
}

SparseBackend parse_sparse_backend(const std::string& s) {
  for (auto b : {SparseBackend::kAuto, SparseBackend::kCholmod, SparseBackend::kEigen})
    if (s == to_string(b)) return b;
  throw InputError("", 0, "linear-solver", "unknown sparse backend '" + s + "' (auto, cholmod, eigen)");
}

OrderingMethod parse_ordering(const std::string& s) {
  for (auto m : {OrderingMethod::kAuto, OrderingMethod::kAmd, OrderingMethod::kMetis, OrderingMethod::kNesdis,
                 OrderingMethod::kNatural})
    if (s == to_string(m)) return m;
  throw InputError("", 0, "ordering", "unknown ordering '" + s + "' (auto, amd, metis, nesdis, natural)");
}

bool cholmod_available() {
#ifdef SLAMKIT_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

std::unique_ptr<SparseCholesky> make_sparse_cholesky(SparseBackend backend, OrderingMethod ordering, int blas_threads) {
#ifdef SLAMKIT_HAVE_CHOLMOD
  if (backend != SparseBackend::kEigen) return make_cholmod_cholesky(ordering, blas_threads);
#else
  (void)blas_threads;
  if (backend == SparseBackend::kCholmod)
    throw InputError("", 0, "linear-solver", "this slamkit was built without CHOLMOD");
#endif
  return make_eigen_cholesky(ordering);
}

}  // namespace slamkit
