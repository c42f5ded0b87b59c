// SPDX-License-Identifier: MIT
#include "src/live/tui/tui.h"

#include <curses.h>
#include <unistd.h>

#include <chrono>
#include <clocale>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "src/live/present.h"
#include "src/live/tui/screen.h"
#include "src/live/tui/tui_text.h"

namespace infocus {

namespace {

using Clock = std::chrono::steady_clock;

// ~15 redraws a second: smooth for a hand on a focus ring, cheap for the pipeline.
constexpr auto kRedrawPeriod = std::chrono::milliseconds(66);
// getch's wait: short, so keys answer at once and the loop never holds anything up.
constexpr int kKeyTimeoutMs = 30;
// How long a control's error stays on the status line.
constexpr auto kErrorShown = std::chrono::seconds(4);

volatile std::sig_atomic_t gSignalled = 0;

void onSignal(int) {
    gSignalled = 1;
}

// The terminal in curses mode for the guard's lifetime, SIGINT and SIGTERM turned into a flag the
// loop checks; the destructor gives the terminal and the signals back on every way out, an
// exception included.
class Terminal {
public:
    Terminal() = default;
    Terminal(const Terminal&) = delete;
    Terminal& operator=(const Terminal&) = delete;

    Status open() {
        if (!isatty(STDIN_FILENO) || !isatty(STDOUT_FILENO)) {
            return makeError(ErrorKind::Unsupported,
                             "the terminal view needs a terminal on stdin and stdout; use --ui "
                             "text or --ui json when piping");
        }
        // newterm, not initscr: initscr exits the process on a bad TERM.
        screen_ = newterm(nullptr, stdout, stdin);
        if (!screen_) {
            return makeError(ErrorKind::Unsupported,
                             "cannot drive the terminal (TERM=" +
                                 std::string(getenv("TERM") ? getenv("TERM") : "unset") +
                                 "); set TERM to your terminal's type or use --ui text");
        }
        set_term(screen_);
        cbreak();
        noecho();
        nonl();
        keypad(stdscr, TRUE);
        curs_set(0);
        set_escdelay(25);
        timeout(kKeyTimeoutMs);
        tui::initColours();

        gSignalled = 0;
        struct sigaction sa = {};
        sa.sa_handler = onSignal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &oldInt_);
        sigaction(SIGTERM, &sa, &oldTerm_);
        return {};
    }

    ~Terminal() {
        if (!screen_) return;
        sigaction(SIGINT, &oldInt_, nullptr);
        sigaction(SIGTERM, &oldTerm_, nullptr);
        endwin();
        delscreen(screen_);
    }

private:
    SCREEN* screen_ = nullptr;
    struct sigaction oldInt_ = {};
    struct sigaction oldTerm_ = {};
};

}  // namespace

Status runTui(LiveView& view, const RunLimits& limits, bool fromSim) {
    std::setlocale(LC_ALL, "");
    Terminal terminal;
    if (Status st = terminal.open(); !st) return st;

    const RunClock clock(limits);
    const Clock::time_point start = Clock::now();
    Clock::time_point lastDraw = start - kRedrawPeriod;
    Clock::time_point errorUntil = start;
    tui::ScreenNotes notes;
    notes.fromSim = fromSim;
    bool dirty = true;

    // A control's error goes to the status line for a few seconds; success leaves the state's.
    auto control = [&](const Status& st) {
        if (st) return;
        notes.status = st.error().message;
        notes.statusIsError = true;
        errorUntil = Clock::now() + kErrorShown;
        dirty = true;
    };

    for (;;) {
        if (gSignalled) return {};
        const std::shared_ptr<const LiveState> state = view.state();
        const Clock::time_point now = Clock::now();
        if (clock.done(state.get())) return {};
        if (view.ended()) return view.endStatus();

        if (!notes.status.empty() && now >= errorUntil) {
            notes.status.clear();
            notes.statusIsError = false;
        }
        if (dirty || now - lastDraw >= kRedrawPeriod) {
            tui::drawScreen(state.get(), notes);
            refresh();
            lastDraw = now;
            dirty = false;
        }

        const int key = getch();
        if (key == ERR) continue;
        dirty = true;
        if (key == KEY_RESIZE) continue;
        present::Key k = present::Key::Char;
        if (key == KEY_LEFT) k = present::Key::Left;
        if (key == KEY_RIGHT) k = present::Key::Right;
        if (key == KEY_SLEFT) k = present::Key::ShiftLeft;
        if (key == KEY_SRIGHT) k = present::Key::ShiftRight;
        if (key == 27) k = present::Key::Escape;
        const char ch = key > 0 && key < 128 ? static_cast<char>(key) : 0;
        const present::Action action = present::actionForKey(k, ch);
        if (action == present::Action::Quit) return {};
        control(present::apply(action, view, state.get()));
    }
}

namespace {

class TuiFace final : public Face {
public:
    explicit TuiFace(bool fromSim) : fromSim_(fromSim) {}
    Status prepare(LiveOptions&) override { return {}; }
    Status run(LiveView& view, const RunLimits& limits) override {
        return runTui(view, limits, fromSim_);
    }

private:
    bool fromSim_;
};

}  // namespace

std::unique_ptr<Face> makeTuiFace(const FaceSettings& settings) {
    return std::make_unique<TuiFace>(settings.fromSim);
}

}  // namespace infocus
