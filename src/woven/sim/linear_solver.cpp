#include "woven/sim/linear_solver.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/CholmodSupport>
#include <dlfcn.h>
#include <omp.h>
#include <tbb/global_control.h>

#include "woven/common/error.hpp"
#include "woven/sim/split_cholesky.hpp"

namespace woven::sim {

namespace {
/// The two-thread factorisation (SplitCholesky) is used from this many unknowns on each side of
/// the top separator (below it the threads' start-up and the separator's dense work outweigh
/// the halved factorisation), with a separator of at most so many unknowns (its dense factor).
constexpr int kMinSplitSide = 2000;
constexpr int kMaxSplitSeparator = 4096;
/// Solves with the split factor run its sides on two threads from this many unknowns a side: a
/// solve at 51 x 51 particles (3900 a side) takes 0.67 ms on one thread, 0.78 ms on two (the
/// worker's wake-up), at 101 x 101 8.7 and 5.9 ms (bench_model newton_solve_split).
constexpr int kMinParallelSolveSide = 8000;
}  // namespace

struct NewtonLinearSolver::Factor {
    Factor()
    {
        // The matrix comes in its fill-reducing order (fill_reducing_order): factorised as it
        // is, CHOLMOD reads it in place instead of making two permuted copies at every
        // factorisation (4.5 % of the 101 x 101 cube's time, 58 MB at 201 x 201).
        llt.cholmod().nmethods = 1;
        llt.cholmod().method[0].ordering = CHOLMOD_NATURAL;
        llt.cholmod().postorder = 0;  // the order is postordered already
        llt.cholmod().print = 0;      // a failure is handled (a shift), not printed to stdout
    }
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const
    {
        if (!split) return llt.solve(b);
        return split->solve(b, parallel_solves());
    }
    /// y = A p (A's lower triangle given), the CG's product: with a split factor on the sides'
    /// two threads (3-5 % of a CG iteration at 201 x 201, on one thread before).
    void product(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& p, Eigen::VectorXd& y) const
    {
        if (split && A.cols() == split->size()) SplitCholesky::symmetric_product(A, split->split(), p, y, parallel_solves());
        else y.noalias() = A.selfadjointView<Eigen::Lower>() * p;
    }
    bool parallel_solves() const
    {
        const SplitCholesky::Split& s = split->split();
        return std::min(s.side_end, s.separator_begin - s.side_end) >= kMinParallelSolveSide;
    }

    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
    /// With a large matrix: the two sides of its top separator (at once from two threads), in
    /// place of llt.
    std::unique_ptr<SplitCholesky> split;
    /// The structure last analysed for llt (H's column starts and row indices; values are not kept).
    std::vector<int> outer, inner;
    bool analysed = false;
    int threads = 1;  ///< oneTBB's thread count at the analysis
};

NewtonLinearSolver::NewtonLinearSolver() : NewtonLinearSolver(Options{}) {}

NewtonLinearSolver::NewtonLinearSolver(Options options) : options_(options), factor_(std::make_unique<Factor>()) {}

std::vector<int> fill_reducing_order(int size, const std::vector<int>& column_starts, const std::vector<int>& rows)
{
    if (size == 0) return {};
    cholmod_common common;
    cholmod_start(&common);
    // Nested dissection orders a cloth grid with ~20 % less fill than AMD; postordered, as
    // CHOLMOD's own analysis does.
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_NESDIS;
    common.supernodal = CHOLMOD_SIMPLICIAL;  // the order only: no supernodal symbolic factor
    cholmod_sparse pattern{};
    pattern.nrow = pattern.ncol = static_cast<size_t>(size);
    pattern.nzmax = rows.size();
    pattern.p = const_cast<int*>(column_starts.data());
    pattern.i = const_cast<int*>(rows.data());
    pattern.stype = -1;  // symmetric, its lower triangle read
    pattern.itype = CHOLMOD_INT;
    pattern.xtype = CHOLMOD_PATTERN;
    pattern.dtype = CHOLMOD_DOUBLE;
    pattern.sorted = 1;
    pattern.packed = 1;
    cholmod_factor* symbolic = cholmod_analyze(&pattern, &common);
    std::vector<int> order;
    if (symbolic) {
        const int* perm = static_cast<const int*>(symbolic->Perm);
        order.assign(perm, perm + size);
        cholmod_free_factor(&symbolic, &common);
    }
    cholmod_finish(&common);
    if (order.empty()) throw RuntimeError("fast solver: the Newton matrix could not be ordered");
    return order;
}

void NewtonLinearSolver::release()
{
    factor_.reset();
    factor_ = std::make_unique<Factor>();
    failed_attempts_ = attempts_to_skip_ = 0;
}

NewtonLinearSolver::~NewtonLinearSolver() = default;

bool NewtonLinearSolver::split_factorization() const { return factor_->split != nullptr; }

namespace {

/// Runs CHOLMOD's OpenMP loops and its dense (BLAS) kernels on the calling thread. CHOLMOD 3
/// asks for a fixed number of threads (4) in its supernodal loops whatever omp_set_num_threads
/// says; on a 2-core machine the oversubscribed, spinning threads more than doubled the 51 x 51
/// cube's wall time (20-25 s, 9 s with this guard, one thread). A threaded BLAS sums in an order
/// that depends on its thread count (--threads 1 and 2 differed by 2e-17 m): on one thread every
/// thread count gives the same bits.
class SerialOpenMP {
public:
    SerialOpenMP() : levels_(omp_get_max_active_levels()), blas_(blas_threads())
    {
        omp_set_max_active_levels(0);
        if (blas_ > 1) set_blas_threads(1);
    }
    ~SerialOpenMP()
    {
        omp_set_max_active_levels(levels_);
        if (blas_ > 1) set_blas_threads(blas_);
    }
    SerialOpenMP(const SerialOpenMP&) = delete;
    SerialOpenMP& operator=(const SerialOpenMP&) = delete;

private:
    int levels_, blas_;
};

bool same_structure(const Eigen::SparseMatrix<double>& a, const std::vector<int>& outer, const std::vector<int>& inner)
{
    if (static_cast<size_t>(a.outerSize()) + 1 != outer.size() || static_cast<size_t>(a.nonZeros()) != inner.size()) return false;
    return std::equal(outer.begin(), outer.end(), a.outerIndexPtr()) && std::equal(inner.begin(), inner.end(), a.innerIndexPtr());
}
}  // namespace

void NewtonLinearSolver::factorize(const Eigen::SparseMatrix<double>& matrix)
{
    const SerialOpenMP serial;
    Factor& f = *factor_;
    Eigen::SparseMatrix<double> compressed;  // only for a matrix in uncompressed mode
    if (!matrix.isCompressed()) {
        compressed = matrix;
        compressed.makeCompressed();
    }
    const Eigen::SparseMatrix<double>& H = matrix.isCompressed() ? matrix : compressed;
    // H itself goes to CHOLMOD, as symmetric with its lower triangle stored (stype -1): CHOLMOD
    // ignores the entries above the diagonal, so no triangle is copied (at 201 x 201 a copy
    // and the kept pattern were 2 x 28 MB, and the copy 1.5 % of the 51 x 51 drape's time).
    const int threads = static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const bool same = f.analysed && threads == f.threads && (f.split ? f.split->analysed_for(H) : same_structure(H, f.outer, f.inner));
    if (!same) {
        f.split.reset();
        std::optional<SplitCholesky::Split> split;
        // Split whatever the thread count (one thread factorises the two sides one after the
        // other): the same sums, so the same bits at 1, 2 and 4 threads.
        split = SplitCholesky::find(H, kMinSplitSide, kMaxSplitSeparator);
        // The split checks a pattern against its own index arrays; the whole factor keeps a
        // copy of it (9.6 MB at 201 x 201).
        if (split) {
            f.split = std::make_unique<SplitCholesky>(H, *split);
            std::vector<int>().swap(f.outer);
            std::vector<int>().swap(f.inner);
        } else {
            f.llt.analyzePattern(H);
            f.outer.assign(H.outerIndexPtr(), H.outerIndexPtr() + H.outerSize() + 1);
            f.inner.assign(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros());
        }
        f.analysed = true;
        f.threads = threads;
    }
    // Round-off can leave a nearly singular H (an unloaded thread, a long static step) just
    // short of positive definite: shift the diagonal until the factorisation succeeds.
    double shift = 0;
    const double scale = H.diagonal().cwiseAbs().maxCoeff();
    for (int attempt = 0; attempt < 8; ++attempt) {
        ++factorizations_;
        if (f.split) {
            if (f.split->factorize(H, shift, threads >= 2)) return;
        } else {
            f.llt.setShift(shift);
            f.llt.factorize(H);
            if (f.llt.info() == Eigen::Success) return;
        }
        shift = shift == 0 ? 1e-12 * scale : 100 * shift;
    }
    f.analysed = false;
    throw RuntimeError("fast solver: the Newton matrix could not be factorised");
}

bool NewtonLinearSolver::preconditioned_cg(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& rhs, Eigen::VectorXd& d)
{
    return truncated_cg(H, rhs, d, options_.relative_tolerance, options_.max_cg_iterations, options_.cg_rate_check_after) == CgEnd::CONVERGED;
}

NewtonLinearSolver::CgEnd NewtonLinearSolver::truncated_cg(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& rhs, Eigen::VectorXd& d,
                                                           double tolerance, int max_iterations, int rate_check_after)
{
    const double initial = rhs.norm(), target = tolerance * initial;
    d.setZero(rhs.size());
    Eigen::VectorXd r = rhs, z = factor_->solve(r), p = z, Ap(rhs.size());
    double rz = r.dot(z);
    for (int k = 0; k < max_iterations; ++k) {
        const double residual = r.norm();
        if (residual <= target) return CgEnd::CONVERGED;
        // |r_k| (|r_k| / |r_0|)^((max - k) / k): the residual at the cap at the mean rate so far.
        if (rate_check_after > 0 && k >= rate_check_after &&
            residual * std::pow(residual / initial, static_cast<double>(max_iterations - k) / k) > target)
            return CgEnd::LIMIT;
        factor_->product(A, p, Ap);
        const double pAp = p.dot(Ap);
        if (!(pAp > 0)) {
            if (k == 0) d = z;  // P^-1 rhs: the projected Newton step
            return CgEnd::NEGATIVE_CURVATURE;
        }
        const double a = rz / pAp;
        d += a * p;
        r -= a * Ap;
        ++cg_iterations_;
        z = factor_->solve(r);
        const double rz_next = r.dot(z);
        p = z + (rz_next / rz) * p;
        rz = rz_next;
    }
    return r.norm() <= target ? CgEnd::CONVERGED : CgEnd::LIMIT;
}

void NewtonLinearSolver::solve_exact(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& P, const Eigen::VectorXd& rhs,
                                     Eigen::VectorXd& d, double tolerance)
{
    solve_exact([&](bool exact) -> const Eigen::SparseMatrix<double>& { return exact ? A : P; }, rhs, d, tolerance);
}

void NewtonLinearSolver::solve_exact(const MatrixSource& matrix, const Eigen::VectorXd& rhs, Eigen::VectorXd& d, double tolerance)
{
    const SerialOpenMP serial;
    if (factor_->analysed && truncated_cg(matrix(true), rhs, d, tolerance, options_.max_cg_iterations) != CgEnd::LIMIT) return;
    factorize(matrix(false));
    // With a fresh factor the last iterate is kept whatever the end: a descent direction.
    truncated_cg(matrix(true), rhs, d, tolerance, 4 * options_.max_cg_iterations);
}

void NewtonLinearSolver::solve(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& rhs, Eigen::VectorXd& d)
{
    const SerialOpenMP serial;
    if (factor_->analysed && attempts_to_skip_ == 0) {
        if (preconditioned_cg(H, rhs, d)) {
            failed_attempts_ = 0;
            return;
        }
        failed_attempts_ = std::min(failed_attempts_ + 1, 30);
        attempts_to_skip_ = std::min((1 << failed_attempts_) - 1, options_.max_skipped_attempts);
    } else if (attempts_to_skip_ > 0) {
        --attempts_to_skip_;
    }
    factorize(H);
    d = factor_->solve(rhs);
}

void set_blas_threads(int threads)
{
    // OpenBLAS reads its thread count at load time; its setter is looked up at run time so that
    // any BLAS works.
    using Setter = void (*)(int);
    static const auto setter = reinterpret_cast<Setter>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    if (setter) setter(threads);
}

int blas_threads()
{
    using Getter = int (*)();
    static const auto getter = reinterpret_cast<Getter>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    return getter ? getter() : 0;
}

}  // namespace woven::sim
