// "did you mean ...?" for a mistyped command or option: the known name nearest to what was typed
// by edit distance, when it is near enough to be a typo.
#pragma once

#include <string>
#include <vector>

namespace kiln {

// Levenshtein distance (insertions, deletions, substitutions of one byte each).
size_t editDistance(const std::string& a, const std::string& b);

// The nearest of names within a third of the typed word's length (at least 1, at most 3 edits),
// or a name the typed word starts (an unambiguous prefix); empty when none is near.
std::string nearestName(const std::string& typed, const std::vector<std::string>& names);

// " (did you mean 'NAME'?)" or "".
std::string didYouMean(const std::string& typed, const std::vector<std::string>& names);

}  // namespace kiln
