#pragma once
// The Newton systems H d = -g of the fast solver. A supernodal sparse Cholesky factorisation
// (CHOLMOD, nested-dissection ordering) is expensive (~60 ms at 51 x 51 particles) while a
// solve with it is cheap (~1 ms), and H changes little from one Newton iteration to the next:
// so the last factorisation preconditions a conjugate-gradient solve with the current H, and H
// is factorised afresh only when that stops converging quickly. Near rest the PSD matrix is a
// poor model of the energy's soft modes (the projected terms drop their negative parts): there
// the same factor preconditions CG on the exact Hessian instead (truncated Newton-CG), which
// stops at the first direction of negative curvature (Steihaug), so the step stays a descent
// direction. A large matrix is factorised in two halves, split at the top separator of its
// nested-dissection tree (split_cholesky.hpp): at once from two threads, one after the other on
// one, the same sums and so the same bits either way.
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Sparse>

namespace woven::sim {

class NewtonLinearSolver {
public:
    struct Options {
        double relative_tolerance = 1e-6;  ///< |H d + g| <= tol |g|
        int max_cg_iterations = 12;        ///< beyond this, H is factorised afresh
        /// After k stale-factor CG attempts in a row that failed, solve() factorises directly
        /// the next min(2^k - 1, this) times before trying the stale factor again: in the stiff
        /// threads' fall nearly every attempt fails, and the failed CG cost a third of the
        /// 51 x 51 cube's time (5848 CG iterations for 371 Newton iterations).
        int max_skipped_attempts = 15;
        /// A stale-factor CG attempt of solve() gives up from this many iterations on (0: never)
        /// once its residual, falling on at its mean rate so far, would still be above the
        /// tolerance after max_cg_iterations: a failed attempt then costs a few solves, not
        /// max_cg_iterations (at 201 x 201 particles 12 solves cost about one factorisation).
        /// The same drapes, 4-5 % faster at 51 and 101 x 101 (bench/NOTES.md "a stale factor's CG gives up early").
        int cg_rate_check_after = 3;
    };
    NewtonLinearSolver();
    explicit NewtonLinearSolver(Options options);
    ~NewtonLinearSolver();
    NewtonLinearSolver(const NewtonLinearSolver&) = delete;
    NewtonLinearSolver& operator=(const NewtonLinearSolver&) = delete;

    /// Solves H d = rhs for symmetric positive definite H, of which the lower triangle is read
    /// (an upper one is ignored), in the order it comes: give it in a fill-reducing order
    /// (fill_reducing_order, SparseAssembly). Throws RuntimeError if H cannot be factorised even
    /// with a diagonal shift.
    void solve(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& rhs, Eigen::VectorXd& d);
    /// Solves A d = rhs to |A d - rhs| <= tolerance |rhs| by CG preconditioned with the factor
    /// of the positive definite P (factorised afresh when the last factor no longer gives
    /// convergence within max_cg_iterations). A is the exact, possibly indefinite Hessian: at
    /// a direction of negative curvature CG stops with its last iterate (the preconditioned
    /// right-hand side P^-1 rhs if it is the first), and after a fresh factorisation it is
    /// given 4 max_cg_iterations and stops there. d is a descent direction for -rhs.
    void solve_exact(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& P, const Eigen::VectorXd& rhs, Eigen::VectorXd& d,
                     double tolerance);
    /// The same with A = matrix(true) and P = matrix(false), which may assemble both into the same
    /// storage: P is asked for only when it is factorised, and A again after it (the fast solver
    /// keeps one Newton matrix, not two: 56 MB at 201 x 201 particles).
    using MatrixSource = std::function<const Eigen::SparseMatrix<double>&(bool exact)>;
    void solve_exact(const MatrixSource& matrix, const Eigen::VectorXd& rhs, Eigen::VectorXd& d, double tolerance);
    /// Frees the factorisation (the next solve factorises afresh): before a new pattern is
    /// built, so that its ordering does not coexist with the old factor.
    void release();
    /// The CG tolerance of solve() (the forcing term of an inexact Newton method).
    void set_tolerance(double relative_tolerance) { options_.relative_tolerance = relative_tolerance; }

    int factorizations() const { return factorizations_; }
    /// Whether the factorisation in use is split at its top separator, its two sides
    /// factorised apart (a large matrix, sim/split_cholesky.hpp; at once with oneTBB allowing
    /// two threads or more), rather than factorised whole.
    bool split_factorization() const;
    int cg_iterations() const { return cg_iterations_; }

private:
    void factorize(const Eigen::SparseMatrix<double>& H);
    /// Preconditioned CG from d = 0; true when converged within the iteration limit.
    bool preconditioned_cg(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& rhs, Eigen::VectorXd& d);
    enum class CgEnd { CONVERGED, LIMIT, NEGATIVE_CURVATURE };
    /// Preconditioned CG on A from d = 0 to `tolerance`, at most `max_iterations`; with
    /// `rate_check_after` > 0 it ends with LIMIT from that iteration on when the residual's mean
    /// rate of decrease so far would not reach the tolerance by `max_iterations`.
    CgEnd truncated_cg(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& rhs, Eigen::VectorXd& d, double tolerance, int max_iterations,
                       int rate_check_after = 0);

    struct Factor;
    Options options_;
    std::unique_ptr<Factor> factor_;
    int factorizations_ = 0, cg_iterations_ = 0;
    int failed_attempts_ = 0;  ///< stale-factor CG attempts of solve() that failed, in a row
    int attempts_to_skip_ = 0;  ///< solve() calls left that factorise without trying the stale factor
};

/// A fill-reducing order of the unknowns of a symmetric matrix of `size` unknowns whose lower
/// triangle has the given pattern (compressed columns, rows ascending): CHOLMOD's nested
/// dissection, postordered. Unknown order[k] comes k-th. Throws RuntimeError on failure.
std::vector<int> fill_reducing_order(int size, const std::vector<int>& column_starts, const std::vector<int>& rows);

/// Threads the BLAS under the factorisation may use (OpenBLAS; a no-op for other BLAS).
void set_blas_threads(int threads);
/// The BLAS's thread count (OpenBLAS), or 0 when it cannot be asked.
int blas_threads();

}  // namespace woven::sim
