// Helpers of the long-render tests (checkpoints, resume, merge): the kiln binary run with a kill
// at a chosen moment, EXR pixels read back exactly, films compared buffer by buffer.
#pragma once

#include <OpenImageIO/imageio.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "renderer/film/film.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln::test {

// The scene of the long-render tests: small, quick, every kind of light path.
inline const std::string& spheres() {
    static const std::string path = cs184("sky/CBspheres.dae");
    return path;
}

// That scene loaded, with its Embree accelerator.
struct LoadedSpheres {
    Scene scene = loadScene(spheres());
    std::unique_ptr<Accelerator> accel = makeEmbreeAccelerator(scene);
};

// Starts kiln with args, stderr to errFile (and stdout to outFile when given).
inline pid_t startKiln(const std::vector<std::string>& args,
                       const std::string& errFile = "/dev/null", const std::string& outFile = "") {
    pid_t pid = ::fork();
    if (pid == 0) {
        if (!::freopen(errFile.c_str(), "w", stderr)) ::_exit(126);
        if (!outFile.empty() && !::freopen(outFile.c_str(), "w", stdout)) ::_exit(126);
        std::vector<char*> argv{const_cast<char*>(KILN_BINARY)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(KILN_BINARY, argv.data());
        ::_exit(127);
    }
    return pid;
}

// Waits (up to 10 s) until process pid has a handler for signal: kiln has got past loading its
// libraries, so a signal is caught rather than ending it. Linux: /proc/PID/status, SigCgt.
inline bool waitForHandler(pid_t pid, int signal) {
    for (int i = 0; i < 2000; ++i) {
        std::ifstream status("/proc/" + std::to_string(pid) + "/status");
        std::string line;
        while (std::getline(status, line))
            if (line.rfind("SigCgt:", 0) == 0 &&
                (std::stoull(line.substr(7), nullptr, 16) >> (signal - 1)) & 1)
                return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

// The exit code, or 128 + the signal that ended it.
inline int exitCode(int status) {
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs kiln to its end; killAfterMs >= 0 sends signal at that moment.
inline int runKilnProcess(const std::vector<std::string>& args, int killAfterMs = -1,
                          int signal = SIGKILL, const std::string& errFile = "/dev/null") {
    pid_t pid = startKiln(args, errFile);
    if (killAfterMs >= 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(killAfterMs));
        ::kill(pid, signal);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return exitCode(status);
}

inline std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every channel of an EXR as stored (names and raw float bits), for bit-for-bit comparisons.
struct ExrPixels {
    std::vector<std::string> channels;
    std::vector<float> values;
    bool operator==(const ExrPixels& o) const {
        return channels == o.channels && values.size() == o.values.size() &&
               std::memcmp(values.data(), o.values.data(), values.size() * sizeof(float)) == 0;
    }
};

inline ExrPixels readExrPixels(const std::string& path) {
    ExrPixels p;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    if (!in) return p;
    const OIIO::ImageSpec& spec = in->spec();
    p.channels = spec.channelnames;
    p.values.resize(size_t(spec.width) * spec.height * size_t(spec.nchannels));
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, p.values.data()));
    return p;
}

// The film's whole state as bytes (every buffer of Film::buffers()), for exact equality.
inline std::string filmState(const Film& film) {
    std::string bytes;
    for (const FilmBuffer& b : film.buffers())
        bytes.append(static_cast<const char*>(b.data), b.bytes(film.pixelCount()));
    return bytes;
}

}  // namespace kiln::test
