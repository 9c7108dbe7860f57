// The OCIO configs of this process, each read once: a batch or a farm task renders many frames in
// one process, and each frame's checks, preview and decoders asked for the config again (3-4 reads
// of the YAML, 6 ms of a 64x48 frame's 25).
#pragma once

#include <OpenColorIO/OpenColorIO.h>

#include <string>

namespace kiln {

// The config at path, read on first use and kept for the process while the file keeps its size
// and modification time (OCIO configs are immutable and safe to share between threads). Throws
// what OCIO::Config::CreateFromFile throws; a config that failed to read is read again next time.
OCIO_NAMESPACE::ConstConfigRcPtr sharedOcioConfig(const std::string& path);

// The path with the file's inode, size and modification time, and the environment (OCIO's context
// variables and active displays and views): a key that changes when the config is rewritten or the
// environment it is read in changes (a long Python session, a test writing configs one after
// another at one path). A rewrite of the same size within the file system's timestamp granularity
// (a coarse NFS mtime) is not seen.
std::string ocioConfigStamp(const std::string& path);

}  // namespace kiln
