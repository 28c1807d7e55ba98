#pragma once
// A progress bar with ETA on stderr. On a terminal it redraws in place at most every
// 100 ms; otherwise (CI logs) it prints one line per 25 %. Thread-safe update().
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace effigi {

class ProgressBar {
public:
    ProgressBar(std::string label, std::uint64_t total, bool enabled = true);
    ~ProgressBar();

    void update(std::uint64_t delta);
    void finish();
    double elapsedSeconds() const;

private:
    void draw(std::uint64_t done, bool final);

    std::string m_label;
    std::uint64_t m_total;
    bool m_enabled, m_tty, m_finished = false;
    std::atomic<std::uint64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start, m_lastDraw;
    int m_lastQuarter = 0;
    std::mutex m_mutex;
};

} // namespace effigi
