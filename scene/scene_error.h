// The one exception type for bad input: its message is the one-line error the user sees.
#pragma once

#include <stdexcept>
#include <string>

namespace kiln {

class SceneError : public std::runtime_error {
  public:
    SceneError(const std::string& file, const std::string& problem)
        : std::runtime_error(file + ": " + problem) {}
};

}  // namespace kiln
