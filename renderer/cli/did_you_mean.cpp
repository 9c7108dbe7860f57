#include "renderer/cli/did_you_mean.h"

#include <algorithm>

namespace kiln {

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::string nearestName(const std::string& typed, const std::vector<std::string>& names) {
    const size_t limit = std::clamp<size_t>(typed.size() / 3, 1, 3);
    std::string best;
    size_t bestDistance = limit + 1;
    std::vector<std::string> extending;
    for (const std::string& name : names) {
        size_t d = editDistance(typed, name);
        if (d < bestDistance) best = name, bestDistance = d;
        if (typed.size() >= 2 && name.rfind(typed, 0) == 0) extending.push_back(name);
    }
    if (best.empty() && extending.size() == 1) return extending[0];
    return best;
}

std::string didYouMean(const std::string& typed, const std::vector<std::string>& names) {
    std::string near = nearestName(typed, names);
    return near.empty() ? "" : " (did you mean '" + near + "'?)";
}

}  // namespace kiln
