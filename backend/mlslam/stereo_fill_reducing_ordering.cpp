#include "backend/mlslam/stereo_fill_reducing_ordering.hpp"

#include <algorithm>
#include <stdexcept>

#include <cholmod.h>

namespace glmbslam::backend {

std::vector<int> nested_dissection_order(const std::vector<std::vector<int>>& adjacency) {
  const std::size_t n = adjacency.size();
  if (n == 0) return {};
  cholmod_common cc;
  cholmod_start(&cc);
  // the pattern of the symmetric matrix, upper triangle (row ≤ column) with the diagonal
  std::size_t nnz = n;
  for (std::size_t c = 0; c < n; ++c)
    for (int r : adjacency[c]) nnz += static_cast<std::size_t>(r) < c ? 1 : 0;
  cholmod_sparse* A = cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_PATTERN, &cc);
  int* Ap = static_cast<int*>(A->p);
  int* Ai = static_cast<int*>(A->i);
  std::size_t k = 0;
  std::vector<int> rows;
  for (std::size_t c = 0; c < n; ++c) {
    Ap[c] = static_cast<int>(k);
    rows.clear();
    for (int r : adjacency[c])
      if (static_cast<std::size_t>(r) < c) rows.push_back(r);
    rows.push_back(static_cast<int>(c));
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int r : rows) Ai[k++] = r;
  }
  Ap[n] = static_cast<int>(k);
  std::vector<int> perm(n);
  const int ok = cholmod_metis(A, nullptr, 0, 1, perm.data(), &cc);
  cholmod_free_sparse(&A, &cc);
  cholmod_finish(&cc);
  if (!ok) throw std::runtime_error("nested_dissection_order: cholmod_metis failed");
  return perm;
}

}  // namespace glmbslam::backend
