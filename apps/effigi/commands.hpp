#pragma once
#include <string>
#include <vector>

namespace effigi::app {

int render(const std::vector<std::string>& args);
int list(const std::vector<std::string>& args);
int info(const std::vector<std::string>& args);

} // namespace effigi::app
