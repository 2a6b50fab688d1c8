// Pins solveAssignment: optimal (not greedy, not just maximum cardinality), rectangular both ways,
// forbidden pairs left out, and equal to brute force on random problems.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "icanc/core/tracking/hungarian.hpp"

namespace icanc {
namespace {

constexpr double F = kForbiddenCost;

double totalCost(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  double sum = 0.0;
  for (int i = 0; i < static_cast<int>(a.size()); ++i) {
    if (a[i] >= 0) sum += c(i, a[i]);
  }
  return sum;
}

// Checks that `a` is a valid partial assignment of `c`: one entry per row, columns in range and
// used once, no forbidden pair.
void expectValid(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  ASSERT_EQ(static_cast<int>(a.size()), c.rows());
  std::vector<int> uses(c.cols(), 0);
  for (int i = 0; i < c.rows(); ++i) {
    ASSERT_GE(a[i], -1);
    ASSERT_LT(a[i], c.cols());
    if (a[i] < 0) continue;
    EXPECT_LT(c(i, a[i]), kForbiddenCost) << "row " << i;
    EXPECT_EQ(++uses[a[i]], 1) << "column " << a[i] << " used twice";
  }
}

// Cheapest entry first, then the cheapest among the remaining rows/columns.
std::vector<int> greedy(const Eigen::MatrixXd& c) {
  std::vector<int> a(c.rows(), -1);
  std::vector<bool> col_used(c.cols(), false);
  for (int k = 0; k < std::min<int>(c.rows(), c.cols()); ++k) {
    int bi = -1, bj = -1;
    for (int i = 0; i < c.rows(); ++i) {
      for (int j = 0; j < c.cols(); ++j) {
        if (a[i] < 0 && !col_used[j] && c(i, j) < F && (bi < 0 || c(i, j) < c(bi, bj))) {
          bi = i;
          bj = j;
        }
      }
    }
    if (bi < 0) break;
    a[bi] = bj;
    col_used[bj] = true;
  }
  return a;
}

// Unweighted maximum-cardinality matching (Kuhn's augmenting paths, columns tried in order):
// ignores the costs except for forbidding.
bool kuhnAugment(const Eigen::MatrixXd& c, int i, std::vector<int>& col_owner,
                 std::vector<bool>& seen) {
  for (int j = 0; j < c.cols(); ++j) {
    if (c(i, j) >= F || seen[j]) continue;
    seen[j] = true;
    if (col_owner[j] < 0 || kuhnAugment(c, col_owner[j], col_owner, seen)) {
      col_owner[j] = i;
      return true;
    }
  }
  return false;
}
std::vector<int> maxCardinality(const Eigen::MatrixXd& c) {
  std::vector<int> col_owner(c.cols(), -1), a(c.rows(), -1);
  for (int i = 0; i < c.rows(); ++i) {
    std::vector<bool> seen(c.cols(), false);
    kuhnAugment(c, i, col_owner, seen);
  }
  for (int j = 0; j < c.cols(); ++j) {
    if (col_owner[j] >= 0) a[col_owner[j]] = j;
  }
  return a;
}

// Best (most allowed pairs, then lowest cost) over all injective maps of the smaller side.
std::pair<int, double> bruteForce(const Eigen::MatrixXd& c) {
  const int n = c.rows(), m = c.cols();
  const int k = std::min(n, m);
  std::vector<int> perm(std::max(n, m));
  std::iota(perm.begin(), perm.end(), 0);
  std::pair<int, double> best(-1, 0.0);
  do {
    int pairs = 0;
    double cost = 0.0;
    for (int t = 0; t < k; ++t) {
      const double e = n <= m ? c(t, perm[t]) : c(perm[t], t);
      if (e < F) {
        ++pairs;
        cost += e;
      }
    }
    if (pairs > best.first || (pairs == best.first && cost < best.second)) best = {pairs, cost};
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

TEST(Hungarian, BeatsGreedy) {
  Eigen::MatrixXd c(3, 3);
  c << 1, 2, 8,
       2, 8, 8,
       8, 8, 1;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
  EXPECT_DOUBLE_EQ(totalCost(c, a), 5.0);
  // Greedy takes (0,0) first and is left with (1,1): 10.
  EXPECT_DOUBLE_EQ(totalCost(c, greedy(c)), 10.0);
}

TEST(Hungarian, WeightsMatterNotOnlyCardinality) {
  Eigen::MatrixXd c(3, 3);
  c << 1, 5, 5,
       5, 1, 5,
       5, 5, 1;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{0, 1, 2}));
  EXPECT_DOUBLE_EQ(totalCost(c, a), 3.0);
  // An unweighted maximum matching is just as large (augmenting through the lowest free columns
  // it ends on the anti-diagonal) but costs 11.
  const std::vector<int> k = maxCardinality(c);
  EXPECT_EQ(k, (std::vector<int>{2, 1, 0}));
  EXPECT_DOUBLE_EQ(totalCost(c, k), 11.0);
  // Same with gating: the only perfect matchings of this pattern are the diagonal (15) and the
  // rotation (3).
  Eigen::MatrixXd g(3, 3);
  g << 5, 1, F,
       F, 5, 1,
       1, F, 5;
  EXPECT_EQ(solveAssignment(g), (std::vector<int>{1, 2, 0}));
}

TEST(Hungarian, MoreColumnsThanRows) {
  Eigen::MatrixXd c(2, 4);
  c << 9, 1, 2, 9,
       9, 2, 9, 9;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{2, 1}));  // 4, not greedy's 1 + 9
  expectValid(c, a);
}

TEST(Hungarian, MoreRowsThanColumns) {
  Eigen::MatrixXd c(4, 2);
  c << 9, 9,
       1, 2,
       2, 9,
       9, 9;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{-1, 1, 0, -1}));
  expectValid(c, a);
  EXPECT_DOUBLE_EQ(totalCost(c, a), 4.0);
}

TEST(Hungarian, Empty) {
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(solveAssignment(Eigen::MatrixXd(3, 0)), (std::vector<int>{-1, -1, -1}));
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 0)).empty());
}

TEST(Hungarian, ForbiddenPairsAreNeverReturned) {
  Eigen::MatrixXd c(3, 3);
  c << 1, F, F,
       F, F, F,       // nothing allowed: unassigned even though a column is free
       F, 2 * F, 3;   // above kForbiddenCost is forbidden too
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{0, -1, 2}));

  Eigen::MatrixXd only_forbidden = Eigen::MatrixXd::Constant(2, 3, F);
  EXPECT_EQ(solveAssignment(only_forbidden), (std::vector<int>{-1, -1}));

  Eigen::MatrixXd anti(2, 2);
  anti << F, 1,
          1, F;
  EXPECT_EQ(solveAssignment(anti), (std::vector<int>{1, 0}));
}

TEST(Hungarian, MostAllowedPairsFirstThenCost) {
  // Row 0 alone on column 0 costs 0.1, but then row 1 (which can only take column 0) is left
  // out: two pairs for 1.8 win, as with a forbidden cost larger than any allowed sum.
  Eigen::MatrixXd c(2, 2);
  c << 0.1, 0.9,
       0.9, F;
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{1, 0}));
}

TEST(Hungarian, SmallCostsNextToForbiddenKeepPrecision) {
  // Differences of 1e-9 decide; with 1e9 inside the potentials they would be lost.
  Eigen::MatrixXd c(3, 3);
  c << 1e-9, 0, F,
       0, 1e-9, F,
       F, F, 0;
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{1, 0, 2}));
}

// Costs uniform in [-5, 10) when int_max == 0, else scale * {0..int_max}; a fraction
// `forbidden` of the entries forbidden.
void randomAgainstBruteForce(unsigned seed, int int_max, double scale, double forbidden,
                             int trials) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> size(1, 7);
  std::uniform_real_distribution<double> real_cost(-5.0, 10.0);
  std::uniform_int_distribution<int> int_cost(0, std::max(int_max, 1));
  std::bernoulli_distribution forbid(forbidden);
  AssignmentWorkspace ws;  // reused across sizes, as the tracker does
  std::vector<int> reused;
  ComponentWorkspace components;
  std::vector<int> by_components;
  for (int trial = 0; trial < trials; ++trial) {
    const int n = size(rng), m = size(rng);
    Eigen::MatrixXd c(n, m);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        c(i, j) = forbid(rng) ? F : int_max > 0 ? scale * int_cost(rng) : real_cost(rng);
      }
    }
    SCOPED_TRACE(::testing::Message() << "trial " << trial << " (" << n << "x" << m << ")\n"
                                      << c);
    const std::vector<int> a = solveAssignment(c);
    expectValid(c, a);
    const auto best = bruteForce(c);
    const int pairs =
        static_cast<int>(std::count_if(a.begin(), a.end(), [](int j) { return j >= 0; }));
    ASSERT_EQ(pairs, best.first);
    ASSERT_NEAR(totalCost(c, a), best.second, 1e-6 * scale);

    solveAssignment(c, ws, reused);
    ASSERT_EQ(reused, a);

    // Per connected component of allowed pairs: the same optimum (ties may pick another one).
    solveAssignmentByComponents(c, components, by_components);
    expectValid(c, by_components);
    ASSERT_EQ(static_cast<int>(std::count_if(by_components.begin(), by_components.end(),
                                             [](int j) { return j >= 0; })),
              best.first);
    ASSERT_NEAR(totalCost(c, by_components), best.second, 1e-6 * scale);
  }
}

TEST(Hungarian, RandomRealCostsMatchBruteForce) { randomAgainstBruteForce(42, 0, 1.0, 0.25, 400); }
// Mostly forbidden: many small components, as gating makes them in the tracker.
TEST(Hungarian, SparseRandomCostsMatchBruteForceByComponents) {
  randomAgainstBruteForce(11, 0, 1.0, 0.75, 1000);
}
TEST(Hungarian, RandomIntegerCostsWithTiesMatchBruteForce) {
  randomAgainstBruteForce(7, 3, 1.0, 0.25, 400);
}
// Nanometre-scale costs next to forbidden ones: exact only if kForbiddenCost does not enter the
// potentials as such (1e9 there leaves a resolution of ~1e-7 and this fails).
TEST(Hungarian, RandomTinyCostsNextToForbiddenMatchBruteForce) {
  randomAgainstBruteForce(9, 99, 1e-9, 0.4, 2000);
}

TEST(Hungarian, WorksOnABlockOfALargerMatrix) {
  Eigen::MatrixXd big = Eigen::MatrixXd::Constant(5, 6, -100.0);  // outside the block: ignored
  big.topLeftCorner(3, 3) << 1, 2, 8,
                             2, 8, 8,
                             8, 8, 1;
  AssignmentWorkspace ws;
  std::vector<int> a;
  solveAssignment(big.topLeftCorner(3, 3), ws, a);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
}

}  // namespace
}  // namespace icanc
