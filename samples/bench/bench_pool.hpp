// What both halves of shadowkit-bench (bench_geometry.cpp, bench_compare.cpp) run the volume's
// frame with: a persistent thread pool (what an engine's job system provides), the chunks it splits
// the faces into, and the z-fail caps of a range of faces.
#pragma once

#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace bench {

// A persistent pool: pool(n, fn) runs fn(0..n-1) on the workers and the calling thread, returns
// when all are done.
class Pool {
public:
    explicit Pool(std::size_t threads) {
        for (std::size_t t = 1; t < threads; ++t) workers_.emplace_back([this] { loop(); });
    }
    ~Pool() {
        {
            std::lock_guard<std::mutex> lk(m_);
            stop_ = true;
            ++gen_;
        }
        cv_.notify_all();
        for (auto& w : workers_) w.join();
    }
    template <typename F>
    void operator()(std::size_t n, const F& fn) {
        {
            std::lock_guard<std::mutex> lk(m_);
            job_ = [&fn](std::size_t i) { fn(i); };
            n_ = n;
            next_.store(0);
            done_.store(0);
            ++gen_;
        }
        cv_.notify_all();
        work();
        while (done_.load(std::memory_order_acquire) < n) std::this_thread::yield();
    }

private:
    void work() {
        for (std::size_t i; (i = next_.fetch_add(1)) < n_;) {
            job_(i);
            done_.fetch_add(1, std::memory_order_release);
        }
    }
    void loop() {
        std::uint64_t seen = 0;
        for (;;) {
            std::unique_lock<std::mutex> lk(m_);
            cv_.wait(lk, [&] { return gen_ != seen; });
            seen = gen_;
            if (stop_) return;
            lk.unlock();
            work();
        }
    }
    std::vector<std::thread> workers_;
    std::mutex m_;
    std::condition_variable cv_;
    std::function<void(std::size_t)> job_;
    std::size_t n_ = 0;
    std::atomic<std::size_t> next_{0}, done_{0};
    std::uint64_t gen_ = 0;
    bool stop_ = false;
};

// The first of n items in chunk c of `chunks` (chunk c is [chunk_begin(n, chunks, c),
// chunk_begin(n, chunks, c + 1)); the first n % chunks chunks have one item more).
inline std::size_t chunk_begin(std::size_t n, std::size_t chunks, std::size_t c) {
    return n / chunks * c + std::min(c, n % chunks);
}

// The z-fail caps (VolumeCapMode::LitOnly, dark cap on) of faces [b, e) of `adj`, `facing` one flag
// per face of the whole mesh, written to out[0 .. capacity).
inline shadowkit::VolumeBuffer lit_caps(const shadowkit::SilhouetteAdjacency& adj, const std::uint8_t* facing, std::size_t b,
                                        std::size_t e, std::size_t vertex_count, std::uint32_t* out, std::size_t capacity) {
    return shadowkit::volume_build_caps(adj.faces.data() + 3 * b, 3 * (e - b), facing + b, e - b, vertex_count,
                                        shadowkit::VolumeCapMode::LitOnly, true, out, capacity);
}

}  // namespace bench
