// Runs a kiln executable as a user would (through the shell) and keeps its exit code, stdout and
// stderr; an environment variable set for one scope.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace kiln::test {

struct CliRun {
    int code;
    std::string out, err;
};

inline CliRun runProgram(const std::string& program, const std::string& args) {
    auto dir = std::filesystem::temp_directory_path() / "kiln-tests";
    std::filesystem::create_directories(dir);
    std::string errFile = (dir / ("stderr-" + std::to_string(::getpid()))).string();
    std::string cmd = program + " " + args + " 2>" + errFile;
    CliRun r{};
    FILE* p = ::popen(cmd.c_str(), "r");
    std::array<char, 4096> buf;
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    int status = ::pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream e(errFile);
    r.err.assign(std::istreambuf_iterator<char>(e), {});
    return r;
}

inline CliRun runKiln(const std::string& args) { return runProgram(KILN_BINARY, args); }

// Single-quoted for the shell, whatever the bytes.
inline std::string shellQuoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

struct ScopedEnv {
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        ::setenv(name, value.c_str(), 1);
    }
    // Unset for the scope.
    ScopedEnv(const char* name, std::nullptr_t) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        ::unsetenv(name);
    }
    ~ScopedEnv() { had_ ? (void)::setenv(name_, old_.c_str(), 1) : (void)::unsetenv(name_); }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

  private:
    const char* name_;
    std::string old_;
    bool had_ = false;
};

}  // namespace kiln::test
