#include "icanc/core/tracking/hungarian.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icanc {
namespace {

bool allowed(double c) { return c < kForbiddenCost; }  // also false for NaN and +inf

// Shortest-augmenting-path Hungarian algorithm with row/column potentials (e-maxx formulation),
// for n <= m. a(i, j) is the cost of row i, column j (0-based). On return ws.p[j] (1-based
// columns) holds the 1-based row assigned to column j, or 0.
template <typename Cost>
void hungarian(int n, int m, const Cost& a, AssignmentWorkspace& ws) {
  const double inf = std::numeric_limits<double>::infinity();
  ws.u.assign(n + 1, 0.0);
  ws.v.assign(m + 1, 0.0);
  ws.p.assign(m + 1, 0);
  ws.way.assign(m + 1, 0);
  ws.minv.resize(m + 1);
  ws.used.resize(m + 1);
  std::vector<double>& u = ws.u;
  std::vector<double>& v = ws.v;
  std::vector<int>& p = ws.p;

  for (int i = 1; i <= n; ++i) {
    // Grow an alternating tree from row i (virtual column 0) until a free column is reached,
    // keeping reduced costs a - u - v >= 0 (Dijkstra with potentials).
    p[0] = i;
    int j0 = 0;
    std::fill(ws.minv.begin(), ws.minv.end(), inf);
    std::fill(ws.used.begin(), ws.used.end(), 0);
    do {
      ws.used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (ws.used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < ws.minv[j]) {
          ws.minv[j] = cur;
          ws.way[j] = j0;
        }
        if (ws.minv[j] < delta) {
          delta = ws.minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (ws.used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          ws.minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    // Augment along the path back to the root.
    do {
      const int j1 = ws.way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
}

}  // namespace

void solveAssignment(const Eigen::Ref<const Eigen::MatrixXd>& cost, AssignmentWorkspace& ws,
                     std::vector<int>& row_to_col) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  row_to_col.assign(rows, -1);
  if (rows == 0 || cols == 0) return;

  // Forbidden entries become `big`, chosen so that one forbidden pair more always costs more than
  // any difference in allowed costs: the optimum maximises the allowed pairs first, then
  // minimises their cost. This keeps the numbers small (1e9 would eat the precision of the
  // potentials) and the objective exact.
  double lo = 0.0, hi = 0.0;
  bool any = false;
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      const double c = cost(i, j);
      if (!allowed(c)) continue;
      lo = any ? std::min(lo, c) : c;
      hi = any ? std::max(hi, c) : c;
      any = true;
    }
  }
  if (!any) return;
  const double big = std::abs(hi) + 1.0 + static_cast<double>(std::min(rows, cols)) * (hi - lo);
  const auto clean = [&cost, big](int i, int j) {
    const double c = cost(i, j);
    return allowed(c) ? c : big;
  };

  if (rows <= cols) {
    hungarian(rows, cols, clean, ws);
    for (int j = 1; j <= cols; ++j) {
      if (ws.p[j] != 0) row_to_col[ws.p[j] - 1] = j - 1;
    }
  } else {  // transpose: columns play the rows
    hungarian(cols, rows, [&clean](int i, int j) { return clean(j, i); }, ws);
    for (int j = 1; j <= rows; ++j) {
      if (ws.p[j] != 0) row_to_col[j - 1] = ws.p[j] - 1;
    }
  }
  for (int i = 0; i < rows; ++i) {
    if (row_to_col[i] >= 0 && !allowed(cost(i, row_to_col[i]))) row_to_col[i] = -1;
  }
}

std::vector<int> solveAssignment(const Eigen::MatrixXd& cost) {
  AssignmentWorkspace ws;
  std::vector<int> row_to_col;
  solveAssignment(cost, ws, row_to_col);
  return row_to_col;
}

}  // namespace icanc
