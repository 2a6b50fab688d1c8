// Optimal minimum-cost assignment (Hungarian / Kuhn-Munkres with potentials, O(n^2 m)).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace icanc {

// Cost of a forbidden pairing. Entries >= kForbiddenCost are never returned as assigned.
constexpr double kForbiddenCost = 1e9;

// Minimises the total cost of a one-to-one assignment of rows to columns of a rectangular
// matrix (rows <= cols or rows > cols both allowed). Returns, for each row, its column or -1
// when the row is left unassigned (more rows than columns, or only forbidden columns left).
// Entries must be finite; use kForbiddenCost for gated-out pairs. Forbidden entries act as a
// cost larger than any sum of allowed ones: the result has the most allowed pairs possible and,
// among those, the lowest total cost.
std::vector<int> solveAssignment(const Eigen::MatrixXd& cost);

// Scratch buffers of solveAssignment, reusable across calls so that a caller running every frame
// (the tracker) allocates only when the problem grows.
struct AssignmentWorkspace {
  std::vector<double> u, v, minv;
  std::vector<int> p, way;
  std::vector<char> used;
};

// Same as above, writing into row_to_col (resized to cost.rows()) and reusing `workspace`.
// Accepts blocks and maps (e.g. the top-left corner of a larger preallocated matrix).
void solveAssignment(const Eigen::Ref<const Eigen::MatrixXd>& cost, AssignmentWorkspace& workspace,
                     std::vector<int>& row_to_col);

// Same result as solveAssignment (the same number of allowed pairs and total cost; among equal
// optima either may be returned), solved separately on each connected component of the graph of
// allowed pairs: with gating, n objects cost about n small problems instead of one O(n^3) one.
struct ComponentWorkspace {
  AssignmentWorkspace assignment;
  std::vector<int> parent, rows, cols, component_of, order;
  Eigen::MatrixXd sub_cost;
  std::vector<int> sub_result;
};
void solveAssignmentByComponents(const Eigen::Ref<const Eigen::MatrixXd>& cost,
                                 ComponentWorkspace& workspace, std::vector<int>& row_to_col);

}  // namespace icanc
