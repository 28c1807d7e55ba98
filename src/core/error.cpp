#include "effigi/core/error.hpp"

#include <algorithm>

namespace effigi {

namespace {
// Levenshtein distance, case-insensitive (typos in XML rarely differ only by case).
std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}
} // namespace

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t bestDist = std::max<std::size_t>(2, word.size() / 3) + 1;  // "close" threshold
    for (const auto& c : candidates) {
        std::size_t d = editDistance(word, c);
        if (d < bestDist) {
            bestDist = d;
            best = c;
        }
    }
    return best;
}

} // namespace effigi
