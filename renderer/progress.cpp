#include "renderer/progress.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace kiln {

Progress::Progress(std::string title, uint64_t totalWork, bool enabled)
    : title_(std::move(title)),
      total_(totalWork ? totalWork : 1),
      enabled_(enabled),
      tty_(isatty(2)),
      start_(std::chrono::steady_clock::now()) {
    if (!enabled_) return;
    thread_ = std::thread([this] {
        auto period = tty_ ? std::chrono::milliseconds(250) : std::chrono::milliseconds(5000);
        std::unique_lock lock(mutex_);
        while (!cv_.wait_for(lock, period, [this] { return stop_; })) print(false);
    });
}

Progress::~Progress() { finish(); }

double Progress::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::finish() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
    print(true);
}

void Progress::print(bool final) {
    double t = elapsedSeconds();
    double frac = std::min(1.0, double(done_.load()) / double(total_));
    double mrays = t > 0 ? double(rays_.load()) / t * 1e-6 : 0.0;
    double eta = frac > 0 ? t * (1 - frac) / frac : 0.0;
    if (tty_) {
        constexpr int kWidth = 30;
        int filled = int(frac * kWidth);
        std::fprintf(stderr, "\r%s [%.*s%*s] %5.1f%%  %.2f Mrays/s  %.1fs elapsed  ETA %.1fs ",
                     title_.c_str(), filled, "##############################", kWidth - filled, "",
                     100 * frac, mrays, t, eta);
        if (final) std::fputc('\n', stderr);
    } else {
        std::fprintf(stderr, "%s: %.1f%%  %.2f Mrays/s  %.1fs elapsed  ETA %.1fs\n", title_.c_str(),
                     100 * frac, mrays, t, eta);
    }
    std::fflush(stderr);
}

}  // namespace kiln
