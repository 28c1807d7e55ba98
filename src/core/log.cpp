#include "effigi/core/log.hpp"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace effigi::log {

namespace {
std::atomic<Level> g_level{Level::Warn};
std::mutex g_mutex;
} // namespace

Level level() { return g_level.load(std::memory_order_relaxed); }
void setLevel(Level l) { g_level.store(l); }

void write(Level l, const std::string& msg) {
    static const char* prefix[] = {"error: ", "warning: ", "", ""};
    std::lock_guard lock(g_mutex);
    std::fprintf(stderr, "%s%s\n", prefix[static_cast<int>(l)], msg.c_str());
}

} // namespace effigi::log
