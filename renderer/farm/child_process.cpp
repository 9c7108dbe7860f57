#include "renderer/farm/child_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>

extern char** environ;

namespace kiln::farm {
namespace {

std::atomic<pid_t> runningChild{0};
std::atomic<int> forwarded{0};

extern "C" void forwardSignal(int sig) {
    forwarded.store(sig);
    pid_t child = runningChild.load();
    if (child > 0) ::kill(child, sig);
}

std::vector<char*> argvOf(const std::string& program, const std::vector<std::string>& args) {
    std::vector<char*> argv{const_cast<char*>(program.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    return argv;
}

int waitExitCode(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return 127;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 127;
}

int spawnOrThrow(pid_t& pid, const std::string& program, const std::vector<std::string>& args,
                 const posix_spawn_file_actions_t* actions) {
    std::vector<char*> argv = argvOf(program, args);
    return ::posix_spawnp(&pid, program.c_str(), actions, nullptr, argv.data(), environ);
}

}  // namespace

std::string kilnExecutable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

int lastForwardedSignal() { return forwarded.load(); }

int runForwardingSignals(const std::string& program, const std::vector<std::string>& args) {
    const int signals[3] = {SIGINT, SIGTERM, SIGUSR1};
    struct sigaction action {
    }, previous[3];
    action.sa_handler = forwardSignal;
    sigemptyset(&action.sa_mask);
    for (int i = 0; i < 3; ++i) ::sigaction(signals[i], &action, &previous[i]);
    pid_t pid = 0;
    int err = spawnOrThrow(pid, program, args, nullptr);
    int code = 127;
    if (err == 0) {
        runningChild.store(pid);
        // A signal that came before the child existed is passed on now.
        if (int sig = forwarded.load()) ::kill(pid, sig);
        code = waitExitCode(pid);
        runningChild.store(0);
    }
    for (int i = 0; i < 3; ++i) ::sigaction(signals[i], &previous[i], nullptr);
    if (err != 0) throw std::runtime_error("cannot start " + program + ": " + std::strerror(err));
    return code;
}

CommandResult runCapturing(const std::string& program, const std::vector<std::string>& args) {
    int pipeFds[2];
    if (::pipe2(pipeFds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], 2);
    pid_t pid = 0;
    int err = spawnOrThrow(pid, program, args, &actions);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeFds[1]);
    CommandResult result;
    char buffer[4096];
    for (ssize_t n; (n = ::read(pipeFds[0], buffer, sizeof buffer)) != 0;) {
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) break;
        result.output.append(buffer, size_t(n));
    }
    ::close(pipeFds[0]);
    result.exitCode = err == 0 ? waitExitCode(pid) : 127;
    if (err != 0) result.output = program + ": " + std::strerror(err);
    return result;
}

}  // namespace kiln::farm
