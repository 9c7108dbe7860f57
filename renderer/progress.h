// Progress on stderr: a bar with percentage, rays/s and ETA on a terminal; plain periodic lines
// otherwise.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace kiln {

class Progress {
  public:
    Progress(std::string title, uint64_t totalWork, bool enabled);
    ~Progress();
    void add(uint64_t work, uint64_t rays) {
        done_.fetch_add(work, std::memory_order_relaxed);
        rays_.fetch_add(rays, std::memory_order_relaxed);
    }
    void finish();
    double elapsedSeconds() const;
    uint64_t rays() const { return rays_.load(); }

  private:
    void print(bool final);
    std::string title_;
    uint64_t total_;
    bool enabled_, tty_;
    std::atomic<uint64_t> done_{0}, rays_{0};
    std::chrono::steady_clock::time_point start_;
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
};

}  // namespace kiln
