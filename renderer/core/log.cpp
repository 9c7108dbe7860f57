#include "renderer/core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <utility>

#include "renderer/core/json.h"

namespace kiln {

namespace {

std::atomic<LogLevel> gLevel{LogLevel::Info};
std::atomic<LogFormat> gFormat{LogFormat::Text};

// Lines from render threads and the main thread never interleave within a line.
std::mutex& sinkMutex() {
    static std::mutex m;
    return m;
}

LogSink& sink() {
    static LogSink s = [](const std::string& line) {
        std::fputs(line.c_str(), stderr);
        std::fflush(stderr);
    };
    return s;
}

// An error or warning is one line: a file name with a newline in it (a hostile name) is written
// with the newline escaped, so a reader of stderr sees one message, not two.
std::string oneLine(std::string_view message) {
    std::string out;
    for (char c : message) out += c == '\n' ? "\\n" : c == '\r' ? "\\r" : std::string(1, c);
    return out;
}

std::string textLine(LogLevel level, std::string_view message, std::string_view command) {
    const std::string text = level == LogLevel::Error || level == LogLevel::Warning
                                 ? oneLine(message)
                                 : std::string(message);
    std::string_view label = level == LogLevel::Error     ? "error: "
                             : level == LogLevel::Warning ? "warning: "
                             : level == LogLevel::Debug   ? "debug: "
                                                          : "";
    // A usage error names its command instead of a label: "kiln render: unknown option ...".
    if (!command.empty()) return fmt::format("kiln {}: {}\n", command, text);
    return fmt::format("kiln: {}{}\n", label, text);
}

std::string jsonLine(LogLevel level, std::string_view message, std::string_view command) {
    Json line = {{"event", "log"}, {"level", toString(level)}};
    if (!command.empty()) line["command"] = std::string(command);
    line["message"] = std::string(message);
    return jsonText(line, -1) + "\n";
}

}  // namespace

void setLogLevel(LogLevel level) { gLevel.store(level); }
LogLevel logLevel() { return gLevel.load(); }
void setLogFormat(LogFormat format) { gFormat.store(format); }
bool logEnabled(LogLevel level) { return int(level) <= int(gLevel.load()); }

LogSink setLogSink(LogSink next) {
    std::lock_guard lock(sinkMutex());
    return std::exchange(sink(), std::move(next));
}

void logMessage(LogLevel level, std::string_view message, std::string_view command) {
    if (!logEnabled(level)) return;
    std::string line = gFormat.load() == LogFormat::JsonLines ? jsonLine(level, message, command)
                                                              : textLine(level, message, command);
    std::lock_guard lock(sinkMutex());
    sink()(line);
}

void logLine(std::string_view line) {
    std::string text = std::string(line) + "\n";
    std::lock_guard lock(sinkMutex());
    sink()(text);
}

}  // namespace kiln
