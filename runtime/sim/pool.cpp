#include "runtime/sim/pool.h"

#include <algorithm>

namespace sdv::sim {

Pool::Pool(int threads) {
    for (int p = 1; p < std::max(1, threads); ++p) workers_.emplace_back([this, p] { work(static_cast<size_t>(p)); });
}

Pool::~Pool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    start_.notify_all();
    for (auto& w : workers_) w.join();
}

void Pool::work(size_t part) {
    uint64_t seen = 0;
    for (;;) {
        const std::function<void(size_t)>* fn;
        size_t n;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            start_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            fn = fn_;
            n = n_;
        }
        const size_t k = threads();
        for (size_t i = part; i < n; i += k) (*fn)(i);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (--pending_ == 0) done_.notify_one();
        }
    }
}

void Pool::run(size_t n, const std::function<void(size_t)>& fn, size_t grain) {
    if (workers_.empty() || n < std::max<size_t>(2, grain)) {
        for (size_t i = 0; i < n; ++i) fn(i);
        return;
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        fn_ = &fn;
        n_ = n;
        pending_ = workers_.size();
        ++generation_;
    }
    start_.notify_all();
    const size_t k = threads();
    for (size_t i = 0; i < n; i += k) fn(i);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return pending_ == 0; });
}

}  // namespace sdv::sim
