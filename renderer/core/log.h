// kiln's messages on stderr, in one place: a level filter (--log-level), the "kiln: " prefix with
// "error: " / "warning: " / "debug: " labels as text, or one JSON object a line for a job queue
// ({"event": "log", "level": ..., "message": ...}, beside the progress lines' events).
#pragma once

#include <fmt/format.h>

#include <functional>
#include <string>
#include <string_view>

#include "renderer/core/enum_names.h"

namespace kiln {

enum class LogLevel { Error, Warning, Info, Debug };  // each shows the ones before it
enum class LogFormat { Text, JsonLines };

template <>
struct EnumNames<LogLevel> {
    static constexpr std::pair<LogLevel, const char*> table[] = {{LogLevel::Error, "error"},
                                                                 {LogLevel::Warning, "warning"},
                                                                 {LogLevel::Info, "info"},
                                                                 {LogLevel::Debug, "debug"}};
};

void setLogLevel(LogLevel level);  // default Info
LogLevel logLevel();
void setLogFormat(LogFormat format);  // default Text
bool logEnabled(LogLevel level);

// Where finished lines go (each ends in '\n'); the default writes them to stderr. Returns the one
// before, so a test can capture and restore.
using LogSink = std::function<void(const std::string& line)>;
LogSink setLogSink(LogSink sink);

// One message (no trailing newline needed); command, when given, names the subcommand the
// message is about ("kiln render: ..." for a usage error).
void logMessage(LogLevel level, std::string_view message, std::string_view command = {});

// A line as it is (a JSON event of the caller's), through the same sink, whatever the level.
void logLine(std::string_view line);

template <class... Args>
void logError(fmt::format_string<Args...> format, Args&&... args) {
    logMessage(LogLevel::Error, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void logWarning(fmt::format_string<Args...> format, Args&&... args) {
    if (logEnabled(LogLevel::Warning))
        logMessage(LogLevel::Warning, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void logInfo(fmt::format_string<Args...> format, Args&&... args) {
    if (logEnabled(LogLevel::Info))
        logMessage(LogLevel::Info, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void logDebug(fmt::format_string<Args...> format, Args&&... args) {
    if (logEnabled(LogLevel::Debug))
        logMessage(LogLevel::Debug, fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace kiln
