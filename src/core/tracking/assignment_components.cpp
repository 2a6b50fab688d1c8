// solveAssignmentByComponents: union-find over rows and columns joined by allowed pairs, then
// the Hungarian solver on each component's sub-matrix. Buffers live in the workspace.
#include <algorithm>
#include <numeric>

#include "icanc/core/tracking/hungarian.hpp"

namespace icanc {

namespace {
int findRoot(std::vector<int>& parent, int k) {
  while (parent[k] != k) {
    parent[k] = parent[parent[k]];
    k = parent[k];
  }
  return k;
}
}  // namespace

void solveAssignmentByComponents(const Eigen::Ref<const Eigen::MatrixXd>& cost,
                                 ComponentWorkspace& ws, std::vector<int>& row_to_col) {
  const int n = static_cast<int>(cost.rows()), m = static_cast<int>(cost.cols());
  row_to_col.assign(n, -1);
  if (n == 0 || m == 0) return;
  // Nodes: rows 0..n-1, columns n..n+m-1.
  ws.parent.resize(n + m);
  std::iota(ws.parent.begin(), ws.parent.end(), 0);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      if (!(cost(i, j) < kForbiddenCost)) continue;
      const int a = findRoot(ws.parent, i), b = findRoot(ws.parent, n + j);
      if (a != b) ws.parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Nodes ordered by component (counting sort on the root): rows then columns of each.
  ws.component_of.resize(n + m);
  for (int k = 0; k < n + m; ++k) ws.component_of[k] = findRoot(ws.parent, k);
  ws.order.resize(n + m);
  std::iota(ws.order.begin(), ws.order.end(), 0);
  std::stable_sort(ws.order.begin(), ws.order.end(),
                   [&ws](int a, int b) { return ws.component_of[a] < ws.component_of[b]; });
  for (std::size_t start = 0; start < ws.order.size();) {
    std::size_t end = start;
    ws.rows.clear();
    ws.cols.clear();
    const int root = ws.component_of[ws.order[start]];
    for (; end < ws.order.size() && ws.component_of[ws.order[end]] == root; ++end) {
      const int node = ws.order[end];
      if (node < n) ws.rows.push_back(node);
      else ws.cols.push_back(node - n);
    }
    start = end;
    if (ws.rows.empty() || ws.cols.empty()) continue;  // a lone row or column: unassigned
    const int r = static_cast<int>(ws.rows.size()), c = static_cast<int>(ws.cols.size());
    if (r == 1 && c == 1) {  // the common case with gating: one track, one detection
      row_to_col[ws.rows[0]] = ws.cols[0];
      continue;
    }
    if (ws.sub_cost.rows() < r || ws.sub_cost.cols() < c)
      ws.sub_cost.resize(std::max<Eigen::Index>(r, ws.sub_cost.rows()),
                         std::max<Eigen::Index>(c, ws.sub_cost.cols()));
    for (int b = 0; b < c; ++b)
      for (int a = 0; a < r; ++a) ws.sub_cost(a, b) = cost(ws.rows[a], ws.cols[b]);
    solveAssignment(ws.sub_cost.topLeftCorner(r, c), ws.assignment, ws.sub_result);
    for (int a = 0; a < r; ++a)
      if (ws.sub_result[a] >= 0) row_to_col[ws.rows[a]] = ws.cols[ws.sub_result[a]];
  }
}

}  // namespace icanc
