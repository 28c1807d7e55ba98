#pragma once
// Minimal levelled logging to stderr; renders print progress here too.
#include <fmt/format.h>

#include <cstdio>

namespace effigi::log {

enum class Level { Error = 0, Warn = 1, Info = 2, Debug = 3 };

Level level();
void setLevel(Level l);
void write(Level l, const std::string& msg);

template <typename... Args> void warn(fmt::format_string<Args...> f, Args&&... a) {
    if (level() >= Level::Warn) write(Level::Warn, fmt::format(f, std::forward<Args>(a)...));
}
template <typename... Args> void info(fmt::format_string<Args...> f, Args&&... a) {
    if (level() >= Level::Info) write(Level::Info, fmt::format(f, std::forward<Args>(a)...));
}
template <typename... Args> void debug(fmt::format_string<Args...> f, Args&&... a) {
    if (level() >= Level::Debug) write(Level::Debug, fmt::format(f, std::forward<Args>(a)...));
}

} // namespace effigi::log
