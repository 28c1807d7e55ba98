#include "effigi/core/progress.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <unistd.h>

namespace effigi {

namespace {
std::string formatDuration(double s) {
    if (s < 60) return fmt::format("{:.1f}s", s);
    int total = int(s + 0.5);
    if (total < 3600) return fmt::format("{}m{:02}s", total / 60, total % 60);
    return fmt::format("{}h{:02}m", total / 3600, (total / 60) % 60);
}
} // namespace

ProgressBar::ProgressBar(std::string label, std::uint64_t total, bool enabled)
    : m_label(std::move(label)), m_total(std::max<std::uint64_t>(total, 1)), m_enabled(enabled),
      m_tty(isatty(STDERR_FILENO)), m_start(std::chrono::steady_clock::now()), m_lastDraw(m_start) {}

ProgressBar::~ProgressBar() { finish(); }

double ProgressBar::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void ProgressBar::update(std::uint64_t delta) {
    std::uint64_t done = m_done.fetch_add(delta) + delta;
    if (!m_enabled) return;
    auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock() || m_finished) return;
    if (m_tty) {
        if (now - m_lastDraw < std::chrono::milliseconds(100)) return;
        m_lastDraw = now;
        draw(done, false);
    } else {
        int quarter = int(4 * done / m_total);
        if (quarter > m_lastQuarter && quarter < 4) {
            m_lastQuarter = quarter;
            draw(done, false);
        }
    }
}

void ProgressBar::finish() {
    std::lock_guard lock(m_mutex);
    if (m_finished) return;
    m_finished = true;
    if (m_enabled) draw(m_done.load(), true);
}

void ProgressBar::draw(std::uint64_t done, bool final) {
    double frac = std::min(1.0, double(done) / double(m_total));
    double elapsed = elapsedSeconds();
    std::string eta = frac > 0 && !final ? ", ETA " + formatDuration(elapsed * (1 - frac) / frac) : "";
    constexpr int Width = 30;
    int filled = int(frac * Width);
    std::string bar = std::string(filled, '#') + std::string(Width - filled, '.');
    std::string line = fmt::format("{} [{}] {:5.1f}% ({}{})", m_label, bar, 100 * frac,
                                   formatDuration(elapsed), eta);
    if (m_tty)
        std::fprintf(stderr, "\r%s\033[K%s", line.c_str(), final ? "\n" : "");
    else
        std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

} // namespace effigi
