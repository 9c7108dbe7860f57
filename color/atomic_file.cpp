#include "color/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace kiln {
namespace {

namespace fs = std::filesystem;

std::string systemError(int err) { return std::strerror(err); }

std::string directoryOf(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    return dir.empty() ? "." : dir.string();
}

std::string hostName() {
    char host[256] = "";
    if (gethostname(host, sizeof host - 1) != 0 || !*host) return "host";
    for (char* c = host; *c; ++c)
        if (*c == '/' || *c == '-') *c = '_';
    return host;
}

// ".NAME.tmp-HOST-": hidden, and not matched by the target's own glob.
std::string tempPrefix(const fs::path& p) {
    std::string name = ".";
    return name.append(p.filename().string()).append(".tmp-").append(hostName()).append("-");
}

// Unique per host, process and call: two renders to one -o never share a temporary file.
std::string uniqueTempName(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    fs::path p(path);
    std::string name = tempPrefix(p);
    name.append(std::to_string(getpid())).append("-").append(std::to_string(counter++));
    return (p.parent_path() / name).string();
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temp_(uniqueTempName(path_)) {
    int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw std::runtime_error(path_ + ": cannot create a temporary file in " +
                                 directoryOf(path_) + ": " + systemError(errno));
    file_ = fdopen(fd, "wb");
    if (!file_) {
        ::close(fd);
        ::unlink(temp_.c_str());
        throw std::runtime_error(path_ + ": cannot open a temporary file: " + systemError(errno));
    }
}

AtomicFile::~AtomicFile() {
    proxy_.reset();
    if (file_) std::fclose(file_);
    if (!committed_) ::unlink(temp_.c_str());
}

void AtomicFile::write(const void* data, size_t bytes) {
    if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) failed_ = true;
}

void AtomicFile::flush() {
    if (std::fflush(file_) != 0) failed_ = true;
}

void AtomicFile::commit() {
    proxy_.reset();
    int err = 0;
    if (std::fflush(file_) != 0 || std::ferror(file_)) err = errno ? errno : EIO;
    if (!err && failed_) err = errno ? errno : EIO;
    if (!err && ::fsync(fileno(file_)) != 0) err = errno;
    if (std::fclose(file_) != 0 && !err) err = errno;
    file_ = nullptr;
    if (err) throw std::runtime_error(path_ + ": write failed: " + systemError(err));
    if (::rename(temp_.c_str(), path_.c_str()) != 0)
        throw std::runtime_error(path_ + ": cannot move into place: " + systemError(errno));
    committed_ = true;
    // The rename itself reaches the disk only with the directory.
    int dir = ::open(directoryOf(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

int removeStaleTemporaries(const std::string& path) {
    return removeStaleTemporaries(std::vector<std::string>{path})[0];
}

std::vector<int> removeStaleTemporaries(const std::vector<std::string>& paths) {
    std::vector<int> removed(paths.size(), 0);
    std::vector<std::string> prefixes;
    std::map<fs::path, std::vector<size_t>> byDirectory;
    for (size_t i = 0; i < paths.size(); ++i) {
        prefixes.push_back(tempPrefix(fs::path(paths[i])));
        fs::path dir = fs::path(paths[i]).parent_path();
        byDirectory[dir.empty() ? fs::path(".") : dir].push_back(i);
    }
    std::error_code ec;
    for (const auto& [dir, indices] : byDirectory)
        for (const auto& entry : fs::directory_iterator(dir, ec)) {
            const std::string name = entry.path().filename().string();
            for (size_t i : indices) {
                const std::string& prefix = prefixes[i];
                if (name.rfind(prefix, 0) != 0) continue;
                long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
                // Only this host's, and only of a process that is gone (SIGKILL during a write).
                if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH &&
                    fs::remove(entry.path(), ec))
                    ++removed[i];
                break;
            }
        }
    return removed;
}

void checkOutputSpace(const std::string& dir, uint64_t bytesNeeded) {
    std::string probe = uniqueTempName((fs::path(dir) / "probe").string());
    int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw std::runtime_error("output directory " + dir +
                                 " is not writable: " + systemError(errno));
    ::close(fd);
    ::unlink(probe.c_str());
    struct statvfs st {};
    if (::statvfs(dir.c_str(), &st) != 0) return;  // unknown: the writes will report
    uint64_t avail = uint64_t(st.f_bavail) * uint64_t(st.f_frsize);
    if (bytesNeeded > avail)
        throw std::runtime_error("output directory " + dir + " has " + std::to_string(avail >> 20) +
                                 " MiB free, the outputs need about " +
                                 std::to_string((bytesNeeded >> 20) + 1) + " MiB");
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
    AtomicFile file(path);
    file.write(bytes.data(), bytes.size());
    file.commit();
}

}  // namespace kiln
