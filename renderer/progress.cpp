#include "renderer/progress.h"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "renderer/core/json.h"

namespace kiln {
namespace {

std::atomic<ProgressStyle> style{ProgressStyle::Text};

// Columns of the terminal on stderr ($COLUMNS when the ioctl cannot tell; 80 otherwise).
int terminalColumns() {
    struct winsize ws {};
    if (ioctl(2, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
    if (const char* c = std::getenv("COLUMNS"); c && std::atoi(c) > 0) return std::atoi(c);
    return 80;
}

}  // namespace

void Progress::setStyle(ProgressStyle s) { style.store(s); }

Progress::Progress(std::string title, uint64_t totalWork, bool enabled)
    : title_(std::move(title)),
      total_(totalWork ? totalWork : 1),
      enabled_(enabled),
      tty_(isatty(2)),
      start_(std::chrono::steady_clock::now()) {
    if (!enabled_) return;
    thread_ = std::thread([this] {
        auto period = style.load() == ProgressStyle::Json ? std::chrono::milliseconds(1000)
                      : tty_                              ? std::chrono::milliseconds(250)
                                                          : std::chrono::milliseconds(5000);
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
    if (style.load() == ProgressStyle::Json)
        printJson(frac, mrays, t, eta, final);
    else if (tty_)
        printBar(frac, mrays, t, eta, final);
    else
        std::fputs(fmt::format("{}: {:.1f}%  {:.2f} Mrays/s  {:.1f}s elapsed  ETA {:.1f}s\n",
                               title_, 100 * frac, mrays, t, eta)
                       .c_str(),
                   stderr);
    std::fflush(stderr);
}

void Progress::printBar(double frac, double mrays, double t, double eta, bool final) {
    std::string tail = fmt::format("] {:5.1f}%  {:.2f} Mrays/s  {:.1f}s elapsed  ETA {:.1f}s ",
                                   100 * frac, mrays, t, eta);
    // The bar takes what the line leaves, so the line never wraps.
    int width = std::max(0, terminalColumns() - 1 - int(title_.size() + 2 + tail.size()));
    int filled = int(frac * width);
    std::string line = "\r" + title_ + " [" + std::string(size_t(filled), '#') +
                       std::string(size_t(width - filled), ' ') + tail;
    if (width == 0) line = "\r" + title_ + tail.substr(1);
    std::fputs(line.c_str(), stderr);
    if (final) std::fputc('\n', stderr);
}

void Progress::printJson(double frac, double mrays, double t, double eta, bool final) {
    Json line = {{"event", final ? "done" : "progress"},
                 {"title", title_},
                 {"fraction", frac},
                 {"work_done", done_.load()},
                 {"work_total", total_},
                 {"rays", rays_.load()},
                 {"mrays_per_second", mrays},
                 {"elapsed_seconds", t},
                 {"eta_seconds", eta}};
    std::fputs((jsonText(line, -1) + "\n").c_str(), stderr);
}

StageProgress::StageProgress(std::string stage, bool heartbeat)
    : stage_(std::move(stage)),
      enabled_(style.load() == ProgressStyle::Json),
      start_(std::chrono::steady_clock::now()) {
    if (!enabled_) return;
    print("start");
    if (!heartbeat) return;
    thread_ = std::thread([this] {
        std::unique_lock lock(mutex_);
        while (!cv_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; }))
            print("running");
    });
}

StageProgress::~StageProgress() {
    if (!enabled_) return;
    if (thread_.joinable()) {
        {
            std::lock_guard lock(mutex_);
            stop_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    print("end");
}

void StageProgress::print(const char* state) const {
    double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    Json line = {{"event", "stage"}, {"stage", stage_}, {"state", state}, {"stage_seconds", t}};
    std::fputs((jsonText(line, -1) + "\n").c_str(), stderr);
    std::fflush(stderr);
}

}  // namespace kiln
