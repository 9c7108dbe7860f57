// Progress on stderr: a bar as wide as the terminal with percentage, rays/s and ETA; plain
// periodic lines when stderr is not a terminal; or JSON lines (one object a second and a final one)
// for a job queue. With JSON lines, each stage of the work (load, build, plan, guide_training,
// render, write) also says when it starts, that it is alive once a second, and when it ends.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace kiln {

enum class ProgressStyle { Text, Json };

class Progress {
  public:
    // Process-wide, set once by the command line before rendering.
    static void setStyle(ProgressStyle style);
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
    void printBar(double frac, double mrays, double t, double eta, bool final);
    void printJson(double frac, double mrays, double t, double eta, bool final);
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

// One stage of a command's work, reported while it lives when the progress style is JSON:
// {"event": "stage", "stage", "state": "start"|"running"|"end", "stage_seconds"}, "running" once a
// second (unless the stage has its own progress lines, as the render does). Silent otherwise.
class StageProgress {
  public:
    explicit StageProgress(std::string stage, bool heartbeat = true);
    ~StageProgress();
    StageProgress(const StageProgress&) = delete;
    StageProgress& operator=(const StageProgress&) = delete;

  private:
    void print(const char* state) const;
    std::string stage_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_;
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
};

}  // namespace kiln
