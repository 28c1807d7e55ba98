#pragma once
#include <string>
#include <vector>

namespace effigi::app {

int render(const std::vector<std::string>& args);
int list(const std::vector<std::string>& args);
int info(const std::vector<std::string>& args);
int converge(const std::vector<std::string>& args);
/// Spectral EXR -> RGB EXR or PNG (convert.cpp).
int convert(const std::vector<std::string>& args);

} // namespace effigi::app
