// Output files checked before any work: a name that cannot be written is exit 2 up front, not an
// error after the render, merge or denoise it would have held.
#pragma once

#include <string>
#include <vector>

namespace kiln {

// An output base name (-o OUT) names a file: something after its directory ("dir/" wrote the
// hidden dir/.exr), not "." or "..", in a directory that exists. Throws UsageError.
void checkOutputBase(const std::string& base);

// Each path can be written as AtomicFile writes it: not a directory, and a temporary file beside
// it can be made (the directory takes files; the file system takes the temporary name, which is
// longer than the path's). Throws UsageError naming the path.
void checkOutputFiles(const std::vector<std::string>& paths);

}  // namespace kiln
