// AtomicFile's OpenImageIO proxy, in the image module with the writers that use it
// (color/image_module.h): the rest of AtomicFile needs no OpenImageIO.
#include "color/atomic_file.h"

namespace kiln {
namespace {

// OpenImageIO's stdio proxy with the write counted: a short write is an error OIIO's PNG writer
// would otherwise let pass.
class CheckedProxy final : public OIIO::Filesystem::IOFile {
  public:
    CheckedProxy(FILE* f, bool& failed) : IOFile(f, Write), failed_(failed) {}
    size_t write(const void* buf, size_t size) override {
        size_t n = IOFile::write(buf, size);
        if (n != size) failed_ = true;
        return n;
    }
    size_t pwrite(const void* buf, size_t size, int64_t offset) override {
        size_t n = IOFile::pwrite(buf, size, offset);
        if (n != size) failed_ = true;
        return n;
    }

  private:
    bool& failed_;
};

}  // namespace

OIIO::Filesystem::IOProxy* AtomicFile::proxy() {
    if (!proxy_)
        proxy_ = {new CheckedProxy(file_, failed_), [](OIIO::Filesystem::IOProxy* p) { delete p; }};
    return proxy_.get();
}

}  // namespace kiln
