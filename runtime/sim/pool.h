// The run's worker threads, started once per run (not per tick): `run(n, fn)` calls fn(0) …
// fn(n − 1) spread over the caller and the workers (item i on thread i mod k) and returns when
// all are done. fn(i) must touch only what item i owns, so the result does not depend on the
// number of threads.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sdv::sim {

class Pool {
public:
    explicit Pool(int threads);
    ~Pool();
    Pool(const Pool&) = delete;
    Pool& operator=(const Pool&) = delete;

    // Batches smaller than `grain` run on the caller alone: waking the workers costs tens of
    // microseconds, more than many cheap items.
    void run(size_t n, const std::function<void(size_t)>& fn, size_t grain = 2);
    size_t threads() const { return workers_.size() + 1; }

private:
    void work(size_t part);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable start_, done_;
    const std::function<void(size_t)>* fn_ = nullptr;
    size_t n_ = 0;
    uint64_t generation_ = 0;
    size_t pending_ = 0;
    bool stop_ = false;
};

}  // namespace sdv::sim
