#pragma once
// A sparse Cholesky factorisation split at the top separator of its elimination tree, so that
// two threads factorise the two sides at once (CHOLMOD 3 factorises one supernode after another).
// In a postordered nested-dissection order the matrix is
//     A = [A11 0 A1T; 0 A22 A2T; AT1 AT2 ATT]
// with the separator T last. Each side g is factorised with the separator block appended,
// B_g = [Agg AgT; ATg ATT] = L_g L_g^T, whose last diagonal block C_g satisfies
// C_g C_g^T = ATT - ATg Agg^-1 AgT (positive definite with A). The separator's Schur complement
// is then S = C_1 C_1^T + C_2 C_2^T - ATT, factorised densely, and the factor of A is
// [L11 0 0; 0 L22 0; LT1 LT2 chol(S)] with L11, L22, LT1, LT2 read from the two factors. The
// corners C_g are needed only to form S: the factors' corners then become the identity and side
// 0's holds chol(S), so the split keeps no dense block beside its factors.
// The result does not depend on whether the sides ran at once: the same bits either way.
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace woven::sim {

class SplitCholesky {
public:
    /// The two sides [0, side_end) and [side_end, separator_begin), the separator
    /// [separator_begin, n).
    struct Split {
        int side_end = 0, separator_begin = 0;
    };
    /// The split of a matrix given by its lower triangle (compressed columns, rows ascending,
    /// in a postordered fill-reducing order), or nullopt when its elimination tree has no chain
    /// at its largest tree's root (with the trees after it: at most max_separator columns)
    /// above two independent sides of at least min_side columns each.
    static std::optional<Split> find(const Eigen::SparseMatrix<double>& lower, int min_side, int max_separator);

    /// Analyses the pattern of `lower` for the split (both sides' symbolic factorisations).
    SplitCholesky(const Eigen::SparseMatrix<double>& lower, Split split);
    ~SplitCholesky();
    SplitCholesky(const SplitCholesky&) = delete;
    SplitCholesky& operator=(const SplitCholesky&) = delete;

    /// Factorises lower + shift I (the pattern analysed); false when it is not positive
    /// definite. `parallel`: the two sides on two threads.
    bool factorize(const Eigen::SparseMatrix<double>& lower, double shift, bool parallel);
    /// (lower + shift I)^-1 b with the last successful factorisation.
    Eigen::VectorXd solve(const Eigen::VectorXd& b, bool parallel) const;

    /// Whether `lower` has the pattern analysed (checked against the sides' own index arrays:
    /// no copy of the pattern is kept).
    bool analysed_for(const Eigen::SparseMatrix<double>& lower) const;

    int size() const { return size_; }
    /// y = A p for A symmetric given by its lower triangle `lower` (compressed columns, rows
    /// ascending) in the order `split` describes, as the CG's product: the two sides' columns on
    /// two threads at once when `parallel`, each writing only its side's rows; the second side's
    /// entries in separator rows are added after it, then the separator's columns. Every y_i
    /// sums its terms in the same order either way: the bits do not depend on `parallel`.
    static void symmetric_product(const Eigen::SparseMatrix<double>& lower, const Split& split, const Eigen::VectorXd& p, Eigen::VectorXd& y,
                                  bool parallel);
    /// How many of the two sides' corners C_g the last factorisation read in place from their
    /// factors (the others were copied: a separator over several supernodes).
    int corners_in_place() const;
    const Split& split() const { return split_; }

private:
    struct Side;
    int size_ = 0;
    Split split_;
    std::array<std::unique_ptr<Side>, 2> sides_;
    /// D of J S J = V^T D^2 V (J reversing the separator's order), V unit upper: V is in side
    /// 0's corner above its diagonal.
    Eigen::VectorXd separator_diagonal_;
    bool factorised_ = false;
};

}  // namespace woven::sim
