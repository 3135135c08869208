#include "woven/sim/split_cholesky.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <exception>
#include <new>
#include <utility>

#include <sys/mman.h>

#include <cholmod.h>
#include <omp.h>
#include <tbb/parallel_invoke.h>

#include "woven/common/error.hpp"

// LAPACK (OpenBLAS), with gfortran's hidden string lengths.
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uplo_length);
void dlauum_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uplo_length);
}

namespace woven::sim {

namespace {

/// f(0) and f(1), on two of oneTBB's threads when `parallel` (its workers persist: a thread
/// started per call cost the 51 x 51 cube 5 s of system time); rethrows their first exception.
/// CHOLMOD's OpenMP loops stay on the thread that runs f: OpenMP's max-active-levels is a
/// per-thread setting, and a worker's default let CHOLMOD start 4 threads of its own (the
/// 51 x 51 factorisation took 38 ms instead of 7.5).
template <class F>
void for_both_sides(bool parallel, const F& f)
{
    std::array<std::exception_ptr, 2> errors;
    const auto run = [&](int g) {
        omp_set_max_active_levels(0);
        try {
            f(g);
        } catch (...) {
            errors[g] = std::current_exception();
        }
    };
    if (parallel) {
        tbb::parallel_invoke([&] { run(0); }, [&] { run(1); });
    } else {
        run(0);
        run(1);
    }
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

/// An int array in anonymous pages of its own, which the kernel maps when first written: a side's
/// row numbers are aligned to A's entries, and the other side's columns between its own and the
/// separator's, never written, cost no memory (4.8 MB at 201 x 201 for the first side).
class MappedIntArray {
public:
    explicit MappedIntArray(std::size_t size) : size_(size), bytes_(std::max<std::size_t>(1, size) * sizeof(int))
    {
        void* p = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        data_ = static_cast<int*>(p);
    }
    ~MappedIntArray() { munmap(data_, bytes_); }
    MappedIntArray(const MappedIntArray&) = delete;
    MappedIntArray& operator=(const MappedIntArray&) = delete;
    int* data() { return data_; }
    const int* data() const { return data_; }
    std::size_t size() const { return size_; }
    int& operator[](std::size_t k) { return data_[k]; }
    int operator[](std::size_t k) const { return data_[k]; }

private:
    int* data_ = nullptr;
    std::size_t size_, bytes_;
};

/// The elimination tree of the symmetric matrix whose lower triangle is given (Liu's algorithm
/// with path compression): parent[k] = -1 for a root.
std::vector<int> elimination_tree(const Eigen::SparseMatrix<double>& lower)
{
    const int n = static_cast<int>(lower.cols());
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    // Row k's entries left of the diagonal: the transpose's columns.
    std::vector<int> row_start(n + 1, 0);
    for (int j = 0; j < n; ++j)
        for (int q = outer[j]; q < outer[j + 1]; ++q)
            if (inner[q] > j) ++row_start[inner[q] + 1];
    for (int k = 0; k < n; ++k) row_start[k + 1] += row_start[k];
    std::vector<int> row_columns(row_start[n]), fill(row_start.begin(), row_start.end() - 1);
    for (int j = 0; j < n; ++j)
        for (int q = outer[j]; q < outer[j + 1]; ++q)
            if (inner[q] > j) row_columns[fill[inner[q]]++] = j;
    std::vector<int> parent(n, -1), ancestor(n, -1);
    for (int k = 0; k < n; ++k)
        for (int q = row_start[k]; q < row_start[k + 1]; ++q)
            for (int i = row_columns[q]; i != -1 && i < k;) {
                const int next = ancestor[i];
                ancestor[i] = k;
                if (next == -1) parent[i] = k;
                i = next;
            }
    return parent;
}

}  // namespace

std::optional<SplitCholesky::Split> SplitCholesky::find(const Eigen::SparseMatrix<double>& lower, int min_side, int max_separator)
{
    const int n = static_cast<int>(lower.cols());
    if (n != lower.rows() || n < 2 * min_side + 1 || !lower.isCompressed()) return std::nullopt;
    const std::vector<int> parent = elimination_tree(lower);
    std::vector<int> children(n, 0), descendants(n, 1);
    for (int j = 0; j < n; ++j)
        if (parent[j] >= 0) {
            ++children[parent[j]];
            descendants[parent[j]] += descendants[j];
        }
    // The main tree's root (pinned unknowns, decoupled, are trees of their own). The separator:
    // the chain from it down to the first node with other than one child, and the (small)
    // trees after it, which couple to nothing before.
    int root = -1;
    for (int j = 0; j < n; ++j)
        if (parent[j] < 0 && (root < 0 || descendants[j] > descendants[root])) root = j;
    int separator_begin = root;
    while (separator_begin > 0 && children[separator_begin] == 1 && parent[separator_begin - 1] == separator_begin) --separator_begin;
    if (n - separator_begin > max_separator) return std::nullopt;
    // The sides: a cut m between whole subtrees (no column before it has its parent in
    // [m, separator_begin)), as even as possible.
    int best = -1, reach = -1;
    for (int m = 1; m < separator_begin; ++m) {
        const int p = parent[m - 1];
        if (p >= 0 && p < separator_begin) reach = std::max(reach, p);
        if (reach >= m || m < min_side || separator_begin - m < min_side) continue;
        if (best < 0 || std::abs(2 * m - separator_begin) < std::abs(2 * best - separator_begin)) best = m;
    }
    if (best < 0) return std::nullopt;
    // A's entries never couple the sides (they join a column to its ancestors): checked.
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    for (int j = 0; j < best; ++j)
        for (int q = outer[j]; q < outer[j + 1]; ++q)
            if (inner[q] >= best && inner[q] < separator_begin) return std::nullopt;
    return Split{best, separator_begin};
}

/// One side with the separator appended: B = [Agg AgT; ATg ATT] and its factor. B is read in
/// place from A's value array, as an unpacked matrix whose columns point at A's (a copy of the
/// values for each side at every factorisation was about 20 MB at 201 x 201: 2.4 million entries).
///
/// Once S is formed the factor's corner C (its last diagonal block) is replaced by the identity:
/// a forward solve then leaves -LTg w in the separator's rows, which is all the separator needs
/// of the side (C z with z = -C^-1 LTg w before), and a backward solve takes x_T there as it is.
/// So C's storage holds C C^T while S is formed, and side 0's then holds chol(S): neither
/// product nor S has storage of its own (2 x 11.6 MB at 201 x 201).
struct SplitCholesky::Side {
    int first = 0, end = 0;               ///< the side's columns of A
    int separator_begin = 0, size = 0;    ///< the separator's columns of A: [separator_begin, size)
    std::ptrdiff_t base = 0;              ///< A's first entry that B reads
    std::vector<int> column_starts, column_counts;  ///< B's columns, as offsets from base
    MappedIntArray rows;                  ///< B's row of A's entry base + q (unread entries never written)
    cholmod_common common{};
    cholmod_factor* factor = nullptr;
    /// The corner: the factor's last diagonal block, in place in its last supernode, or
    /// corner_copy when the separator spans several supernodes (the factor's own entries are
    /// then set to the identity at once).
    double* corner_data = nullptr;
    Eigen::Index corner_stride = 0;
    bool corner_in_place = false;
    Eigen::MatrixXd corner_copy;

    using CornerMap = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
    CornerMap corner() const { return CornerMap(corner_data, separator(), separator(), Eigen::OuterStride<>(corner_stride)); }

    int own() const { return end - first; }
    int separator() const { return size - separator_begin; }
    int dimension() const { return own() + separator(); }

    /// f(j, k) for B's columns k = 0, 1, ... and the columns j of A they are.
    template <class F> void for_each_column(const F& f) const
    {
        int k = 0;
        for (int j = first; j < end; ++j) f(j, k++);
        for (int j = separator_begin; j < size; ++j) f(j, k++);
    }
    /// B's row of A's row r.
    int row_of(int r) const { return r < end ? r - first : r - separator_begin + own(); }

    Side(const Eigen::SparseMatrix<double>& lower, int first_column, int end_column, int separator_first)
        : first(first_column), end(end_column), separator_begin(separator_first), size(static_cast<int>(lower.cols())),
          base(lower.outerIndexPtr()[first_column]), rows(static_cast<std::size_t>(lower.outerIndexPtr()[lower.cols()] - base))
    {
        cholmod_start(&common);
        common.nmethods = 1;
        common.method[0].ordering = CHOLMOD_NATURAL;  // the side comes in its fill-reducing order
        common.postorder = 0;
        common.supernodal = CHOLMOD_SUPERNODAL;  // an LL' factor, whose blocks are read below
        common.print = 0;                        // a failure is returned, not printed to stdout
        const int* outer = lower.outerIndexPtr();
        const int* inner = lower.innerIndexPtr();
        column_starts.resize(dimension());
        column_counts.resize(dimension());
        for_each_column([&](int j, int k) {
            column_starts[k] = static_cast<int>(outer[j] - base);
            column_counts[k] = outer[j + 1] - outer[j];
            for (int q = outer[j]; q < outer[j + 1]; ++q) rows[q - base] = row_of(inner[q]);
        });
        cholmod_sparse pattern = matrix(nullptr);
        pattern.xtype = CHOLMOD_PATTERN;
        factor = cholmod_analyze(&pattern, &common);
        if (!factor) {
            cholmod_finish(&common);
            throw RuntimeError("fast solver: the Newton matrix's split could not be analysed");
        }
    }
    ~Side()
    {
        if (factor) cholmod_free_factor(&factor, &common);
        cholmod_finish(&common);
    }
    Side(const Side&) = delete;
    Side& operator=(const Side&) = delete;

    /// Whether `lower` has the pattern of A on this side's columns.
    bool reads(const Eigen::SparseMatrix<double>& lower) const
    {
        const int* outer = lower.outerIndexPtr();
        const int* inner = lower.innerIndexPtr();
        if (outer[first] != base || static_cast<std::size_t>(outer[size] - base) != rows.size()) return false;
        bool same = true;
        for_each_column([&](int j, int k) {
            if (!same || outer[j] - base != column_starts[k] || outer[j + 1] - outer[j] != column_counts[k]) {
                same = false;
                return;
            }
            for (int q = outer[j]; q < outer[j + 1] && same; ++q) same = rows[q - base] == row_of(inner[q]);
        });
        return same;
    }

    /// B over A's values (CHOLMOD only reads them).
    cholmod_sparse matrix(const double* values) const
    {
        cholmod_sparse b{};
        b.nrow = b.ncol = static_cast<std::size_t>(dimension());
        b.nzmax = rows.size();
        b.p = const_cast<int*>(column_starts.data());
        b.nz = const_cast<int*>(column_counts.data());
        b.i = const_cast<int*>(rows.data());
        b.x = const_cast<double*>(values);
        b.stype = -1;
        b.itype = CHOLMOD_INT;
        b.xtype = CHOLMOD_REAL;
        b.dtype = CHOLMOD_DOUBLE;
        b.sorted = 1;
        b.packed = 0;
        return b;
    }

    /// Factorises B + shift I and leaves J C C^T J (J reverses the separator's order) in the
    /// corner's upper triangle; false when B is not positive definite.
    bool factorize(const Eigen::SparseMatrix<double>& lower, double shift)
    {
        cholmod_sparse b = matrix(lower.valuePtr() + base);
        double beta[2] = {shift, 0};
        if (!cholmod_factorize_p(&b, beta, nullptr, 0, factor, &common) && common.status != CHOLMOD_NOT_POSDEF)
            throw RuntimeError("fast solver: the Newton matrix's split could not be factorised");
        if (common.status == CHOLMOD_NOT_POSDEF || factor->minor < factor->n) return false;
        find_corner();
        // C C^T by LAPACK's U U^T on U = J C J, upper: C's lower triangle reversed in place.
        const int s = separator(), stride = static_cast<int>(corner_stride);
        CornerMap c = corner();
        for (int col = 0; col < s; ++col)
            for (int r = col + 1; r < s; ++r) std::swap(c(r, col), c(s - 1 - r, s - 1 - col));
        for (int r = 0; r < s / 2; ++r) std::swap(c(r, r), c(s - 1 - r, s - 1 - r));
        int info = 0;
        dlauum_("U", &s, c.data(), &stride, &info, 1);
        if (info != 0) throw RuntimeError("fast solver: the Newton matrix's separator product failed");
        return true;
    }

    /// Points corner_data at the corner: in place when B's last supernode holds the whole
    /// separator (and no rows below its diagonal block), else a copy from the supernodes that
    /// hold it, whose entries become the identity's.
    void find_corner()
    {
        const int s = separator(), t0 = own();
        const int* super = static_cast<const int*>(factor->super);
        const int* pi = static_cast<const int*>(factor->pi);
        const int* px = static_cast<const int*>(factor->px);
        const int* supernode_rows = static_cast<const int*>(factor->s);
        double* x = static_cast<double*>(factor->x);
        const std::size_t last = factor->nsuper - 1;
        const int k1 = super[last], k2 = super[last + 1], last_height = pi[last + 1] - pi[last];
        if (k1 <= t0 && k2 == dimension() && last_height == k2 - k1) {
            corner_data = x + px[last] + static_cast<std::ptrdiff_t>(t0 - k1) * last_height + (t0 - k1);
            corner_stride = last_height;
            corner_in_place = true;
            return;
        }
        corner_copy.setZero(s, s);
        for (std::size_t sn = 0; sn < factor->nsuper; ++sn) {
            const int first_column = super[sn], end_column = super[sn + 1];
            if (end_column <= t0) continue;
            const int height = pi[sn + 1] - pi[sn];
            const int* r = supernode_rows + pi[sn];
            for (int c = std::max(first_column, t0); c < end_column; ++c) {
                double* column = x + px[sn] + static_cast<std::ptrdiff_t>(c - first_column) * height;
                for (int q = 0; q < height; ++q)
                    if (r[q] >= c) {
                        corner_copy(r[q] - t0, c - t0) = column[q];
                        column[q] = r[q] == c ? 1.0 : 0.0;
                    }
            }
        }
        corner_data = corner_copy.data();
        corner_stride = s;
        corner_in_place = false;
    }

    /// The factor's corner becomes the identity (its lower triangle: what the solves read).
    void corner_to_identity()
    {
        if (!corner_in_place) return;  // done by find_corner
        CornerMap c = corner();
        for (int col = 0; col < separator(); ++col) {
            c(col, col) = 1.0;
            for (int r = col + 1; r < separator(); ++r) c(r, col) = 0.0;
        }
    }

    /// L y = rhs or L^T y = rhs (system CHOLMOD_L or CHOLMOD_Lt) in place.
    void triangular_solve(int system, Eigen::VectorXd& rhs) const
    {
        cholmod_dense b{};
        b.nrow = b.nzmax = b.d = static_cast<std::size_t>(rhs.size());
        b.ncol = 1;
        b.x = rhs.data();
        b.xtype = CHOLMOD_REAL;
        b.dtype = CHOLMOD_DOUBLE;
        cholmod_common& c = const_cast<cholmod_common&>(common);  // CHOLMOD's workspace
        cholmod_dense* y = cholmod_solve(system, factor, &b, &c);
        if (!y) throw RuntimeError("fast solver: a solve with the Newton matrix's split failed");
        std::memcpy(rhs.data(), y->x, sizeof(double) * rhs.size());
        cholmod_free_dense(&y, &c);
    }
};

SplitCholesky::SplitCholesky(const Eigen::SparseMatrix<double>& lower, Split split) : size_(static_cast<int>(lower.cols())), split_(split)
{
    sides_[0] = std::make_unique<Side>(lower, 0, split.side_end, split.separator_begin);
    sides_[1] = std::make_unique<Side>(lower, split.side_end, split.separator_begin, split.separator_begin);
}

SplitCholesky::~SplitCholesky() = default;

bool SplitCholesky::analysed_for(const Eigen::SparseMatrix<double>& lower) const
{
    return lower.cols() == size_ && lower.rows() == size_ && lower.isCompressed() && sides_[0]->reads(lower) && sides_[1]->reads(lower);
}

int SplitCholesky::corners_in_place() const
{
    int in_place = 0;
    for (const std::unique_ptr<Side>& side : sides_)
        if (side->corner_data && side->corner_in_place) ++in_place;
    return in_place;
}

bool SplitCholesky::factorize(const Eigen::SparseMatrix<double>& lower, double shift, bool parallel)
{
    factorised_ = false;
    std::array<bool, 2> ok{};
    for_both_sides(parallel, [&](int g) { ok[g] = sides_[g]->factorize(lower, shift); });
    if (!ok[0] || !ok[1]) return false;
    // J S J = J (C1 C1^T + C2 C2^T - ATT - shift I) J, its upper triangle, in side 0's corner.
    const int s = size_ - split_.separator_begin, t0 = split_.separator_begin;
    Side::CornerMap S = sides_[0]->corner();
    const Side::CornerMap product = sides_[1]->corner();
    for (int c = 0; c < s; ++c)
        for (int r = 0; r <= c; ++r) S(r, c) += product(r, c);
    sides_[1]->corner_to_identity();
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    const double* values = lower.valuePtr();
    for (int c = t0; c < size_; ++c)
        for (int q = outer[c]; q < outer[c + 1]; ++q) S(s - 1 - (inner[q] - t0), s - 1 - (c - t0)) -= values[q];
    for (int c = 0; c < s; ++c) S(c, c) -= shift;
    // J S J = U^T U = V^T D^2 V with V = D^-1 U unit upper: V's strict upper triangle stays in
    // the corner, D on its own, and the corner's diagonal and lower triangle become the identity.
    int info = 0, stride = static_cast<int>(S.outerStride());
    dpotrf_("U", &s, S.data(), &stride, &info, 1);
    if (info < 0) throw RuntimeError("fast solver: the Newton matrix's separator could not be factorised");
    if (info > 0) return false;
    separator_diagonal_.resize(s);
    for (int k = 0; k < s; ++k) separator_diagonal_[k] = S(k, k);
    for (int c = 0; c < s; ++c)
        for (int r = 0; r < c; ++r) S(r, c) /= separator_diagonal_[r];
    sides_[0]->corner_to_identity();
    factorised_ = true;
    return true;
}

namespace {

/// Columns [first, last) of y += A p (A's lower triangle): each column's entries below the
/// diagonal scatter into y up to row `limit` (excluded) and all of them gather into y_c. The
/// entries at rows >= limit are left for scatter_from.
void product_columns(const Eigen::SparseMatrix<double>& lower, const Eigen::VectorXd& p, Eigen::VectorXd& y, int first, int last, int limit)
{
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    const double* value = lower.valuePtr();
    for (int c = first; c < last; ++c) {
        const double pc = p[c];
        double gathered = 0;
        int k = outer[c];
        const int end = outer[c + 1];
        if (k < end && inner[k] == c) gathered = value[k++] * pc;
        for (; k < end; ++k) {
            const int r = inner[k];
            if (r < limit) y[r] += value[k] * pc;
            gathered += value[k] * p[r];
        }
        y[c] += gathered;
    }
}

/// The scatter of columns [first, last) into rows >= limit (what product_columns left).
void scatter_from(const Eigen::SparseMatrix<double>& lower, const Eigen::VectorXd& p, Eigen::VectorXd& y, int first, int last, int limit)
{
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    const double* value = lower.valuePtr();
    for (int c = first; c < last; ++c) {
        const int* begin = inner + outer[c];
        const int* end = inner + outer[c + 1];
        for (const int* it = std::lower_bound(begin, end, limit); it != end; ++it) y[*it] += value[it - inner] * p[c];
    }
}

}  // namespace

void SplitCholesky::symmetric_product(const Eigen::SparseMatrix<double>& lower, const Split& split, const Eigen::VectorXd& p, Eigen::VectorXd& y,
                                      bool parallel)
{
    const int n = static_cast<int>(lower.cols());
    y.setZero(n);
    // Side 0's columns write its rows and the separator's; side 1's only its own rows, at once.
    const int t0 = split.separator_begin;
    for_both_sides(parallel, [&](int g) {
        if (g == 0) product_columns(lower, p, y, 0, split.side_end, n);
        else product_columns(lower, p, y, split.side_end, t0, t0);
    });
    scatter_from(lower, p, y, split.side_end, t0, t0);
    product_columns(lower, p, y, t0, n, n);
}

Eigen::VectorXd SplitCholesky::solve(const Eigen::VectorXd& b, bool parallel) const
{
    if (!factorised_) throw RuntimeError("fast solver: a solve with no factorisation");
    const int s = size_ - split_.separator_begin, t0 = split_.separator_begin;
    // Forward: [w; z] = L_g^-1 [b_g; 0] with the identity corner: z = -LTg w.
    std::array<Eigen::VectorXd, 2> y;
    for_both_sides(parallel, [&](int g) {
        const Side& side = *sides_[g];
        y[g].setZero(side.dimension());
        y[g].head(side.own()) = b.segment(side.first, side.own());
        side.triangular_solve(CHOLMOD_L, y[g]);
    });
    // S x_T = b_T - LT1 w_1 - LT2 w_2, as (V^T D^2 V) J x_T = J (...).
    Eigen::VectorXd reversed = (b.tail(s) + y[0].tail(s) + y[1].tail(s)).reverse();
    const auto unit_upper = std::as_const(*sides_[0]).corner().triangularView<Eigen::UnitUpper>();
    unit_upper.transpose().solveInPlace(reversed);
    for (int k = 0; k < s; ++k) reversed[k] = reversed[k] / separator_diagonal_[k] / separator_diagonal_[k];
    unit_upper.solveInPlace(reversed);
    // Backward: L_g^T [x_g; x_T] = [w; x_T].
    Eigen::VectorXd x(size_);
    x.segment(t0, s) = reversed.reverse();
    for_both_sides(parallel, [&](int g) {
        const Side& side = *sides_[g];
        y[g].tail(s) = x.segment(t0, s);
        side.triangular_solve(CHOLMOD_Lt, y[g]);
        x.segment(side.first, side.own()) = y[g].head(side.own());
    });
    return x;
}

}  // namespace woven::sim
