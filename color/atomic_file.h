// Every file kiln writes goes through AtomicFile: the data lands in a temporary file with a name
// unique to this process and call, is flushed to disk, and only then renamed over the target. A
// reader never sees a half-written file, two processes writing the same target never mix, and a
// write that failed (disk full, I/O error) is reported instead of leaving a truncated file.
#pragma once

#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace kiln {

class AtomicFile {
  public:
    // Creates the temporary file beside path. Throws std::runtime_error naming path.
    explicit AtomicFile(std::string path);
    ~AtomicFile();  // removes the temporary file unless commit() succeeded
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::string& path() const { return path_; }
    const std::string& tempPath() const { return temp_; }
    // Raw writes; errors are sticky and reported by commit().
    void write(const void* data, size_t bytes);
    // The buffered bytes handed to the temporary file, for a reader that opens it by name.
    void flush();
    // For OpenImageIO writers (ImageOutput::set_ioproxy): the same stream, same error checks.
    OIIO::Filesystem::IOProxy* proxy();
    // Flushes, checks every write, fsyncs, renames over path and fsyncs the directory. Throws
    // std::runtime_error naming path and the system's reason.
    void commit();

  private:
    std::string path_, temp_;
    FILE* file_ = nullptr;
    // Deleted through a function set where the proxy is made (the image module): this side then
    // needs none of OpenImageIO's symbols, its type information included (UBSan's vptr checks).
    using ProxyDeleter = void (*)(OIIO::Filesystem::IOProxy*);
    std::unique_ptr<OIIO::Filesystem::IOProxy, ProxyDeleter> proxy_{nullptr, nullptr};
    bool failed_ = false;  // a write came up short
    bool committed_ = false;
};

// A whole file written through AtomicFile (text reports, pages, manifests).
void writeFileAtomically(const std::string& path, std::string_view bytes);

// Removes the temporary files a killed process of this host left for path (SIGKILL during a
// write); returns how many. Another live process's are kept.
int removeStaleTemporaries(const std::string& path);
// The same for several paths, each directory read once (a batch frame's image, preview and
// checkpoint share one, which holds every frame written so far); how many for each path.
std::vector<int> removeStaleTemporaries(const std::vector<std::string>& paths);

// Before rendering: throws std::runtime_error unless a file can be created in dir and
// bytesNeeded fit its free space.
void checkOutputSpace(const std::string& dir, uint64_t bytesNeeded);

}  // namespace kiln
