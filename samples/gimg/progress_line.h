#pragma once
// A one-line progress report for long runs, rewritten in place on a terminal (stderr); silent
// when stderr is not a terminal or with --quiet, so logs and pipes stay clean.
#include <unistd.h>

#include <cstdarg>
#include <cstdio>

namespace gimg::cli {

class ProgressLine {
public:
    explicit ProgressLine(bool quiet) : on_(!quiet && isatty(STDERR_FILENO)) {}
    ~ProgressLine() { finish(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    bool on() const { return on_; }

    [[gnu::format(printf, 2, 3)]] void show(const char* format, ...) {
        if (!on_) return;
        std::va_list args;
        va_start(args, format);
        std::fputs("\r\033[K", stderr);
        std::vfprintf(stderr, format, args);
        va_end(args);
        std::fflush(stderr);
        shown_ = true;
    }
    // "<what> N%" for a share of the work done in [0, 1], redrawn only when N changes.
    void percent(const char* what, double done) {
        const int now = int(100.0 * done);
        if (now == last_percent_) return;
        last_percent_ = now;
        show("%s %d%%", what, now);
    }
    // Ends the line (before normal output follows).
    void finish() {
        if (shown_) std::fputs("\r\033[K", stderr);
        shown_ = false;
    }

private:
    bool on_;
    bool shown_ = false;
    int last_percent_ = -1;
};

}  // namespace gimg::cli
