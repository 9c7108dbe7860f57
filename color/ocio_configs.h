// The OCIO configs of this process, each read once: a batch or a farm task renders many frames in
// one process, and each frame's checks, preview and decoders asked for the config again (3-4 reads
// of the YAML, 6 ms of a 64x48 frame's 25).
#pragma once

#include <OpenColorIO/OpenColorIO.h>

#include <cstddef>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <utility>

namespace kiln {

// The config at path, read on first use and kept for the process while the file keeps its inode,
// size and modification time and the environment it was read in holds (OCIO_ACTIVE_DISPLAYS,
// _VIEWS, OCIO_INACTIVE_COLORSPACES, the context variables it captured): a long Python session
// that edits the config or sets $SHOT gets it read again. A rewrite of the same size within the
// file system's timestamp granularity (a coarse NFS mtime) is not seen. OCIO configs are immutable
// and safe to share between threads. Throws what OCIO::Config::CreateFromFile throws; a config
// that failed to read is read again next time.
OCIO_NAMESPACE::ConstConfigRcPtr sharedOcioConfig(const std::string& path);

// The path and the generation of its config as sharedOcioConfig holds it now: a key for what is
// made from the config, which changes whenever the config is read again.
std::string ocioConfigStamp(const std::string& path);

// What a process makes from its config for a display, view and look (a checked setup, a display
// processor): made once per read of the config, at most kKept of them (configs read again and
// again start it afresh). A make that throws keeps nothing, so it fails again with its message.
template <class T>
class MadeFromConfig {
  public:
    // configStamp: ocioConfigStamp of the config `make` reads, taken once by the caller, so that
    // what is made and the key it is kept under name the same read.
    template <class Make>
    T get(const std::string& configStamp, const std::string& display, const std::string& view,
          const std::string& look, Make make) {
        const Key key{configStamp, display, view, look};
        std::lock_guard lock(mutex_);
        auto it = made_.find(key);
        if (it == made_.end()) {
            T value = make();
            if (made_.size() >= kKept) made_.clear();
            it = made_.emplace(key, std::move(value)).first;
        }
        return it->second;
    }

  private:
    static constexpr size_t kKept = 32;
    using Key = std::tuple<std::string, std::string, std::string, std::string>;
    std::mutex mutex_;
    std::map<Key, T> made_;
};

}  // namespace kiln
