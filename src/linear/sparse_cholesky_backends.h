// Internal: constructors of the SparseCholesky backends.
#pragma once

#include <memory>

#include "slamkit/linear/sparse_cholesky.h"

namespace slamkit {

#ifdef SLAMKIT_HAVE_CHOLMOD
std::unique_ptr<SparseCholesky> make_cholmod_cholesky(OrderingMethod ordering, int blas_threads);
#endif
std::unique_ptr<SparseCholesky> make_eigen_cholesky(OrderingMethod ordering);

}  // namespace slamkit
