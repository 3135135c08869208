#pragma once
// The thread counts of oneTBB, OpenMP and the BLAS for a scope (process-wide settings).
#include <memory>

namespace woven::sim {

/// For its lifetime: oneTBB and OpenMP on `threads` threads (> 0; 0 leaves them as they are),
/// the BLAS on `blas_threads` (> 0; 0 leaves it); restores what it changed when destroyed.
class ThreadCount {
public:
    ThreadCount(int threads, int blas_threads);
    ~ThreadCount();
    ThreadCount(const ThreadCount&) = delete;
    ThreadCount& operator=(const ThreadCount&) = delete;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace woven::sim
