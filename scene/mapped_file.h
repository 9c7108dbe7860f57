// A read-only memory map of a whole file, for the direct readers (PLY, OBJ).
#pragma once

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "scene/scene_error.h"

namespace kiln {

class MappedFile {
  public:
    explicit MappedFile(const std::string& path) {
        fd_ = ::open(path.c_str(), O_RDONLY);
        if (fd_ < 0) throw SceneError(path, std::string("cannot open: ") + std::strerror(errno));
        struct stat st {};
        ::fstat(fd_, &st);
        size_ = size_t(st.st_size);
        if (size_ == 0) throw SceneError(path, "file is empty");
        data_ = static_cast<const char*>(::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0));
        if (data_ == MAP_FAILED) throw SceneError(path, "cannot map file");
    }
    ~MappedFile() {
        if (data_ && data_ != MAP_FAILED) ::munmap(const_cast<char*>(data_), size_);
        if (fd_ >= 0) ::close(fd_);
    }
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    const char* data() const { return data_; }
    size_t size() const { return size_; }

  private:
    int fd_ = -1;
    const char* data_ = nullptr;
    size_t size_ = 0;
};

}  // namespace kiln
