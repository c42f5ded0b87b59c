// SPDX-License-Identifier: MIT
#include "src/live/window/window.h"

#include <SDL.h>
#include <backends/imgui_impl_sdl.h>
#include <backends/imgui_impl_sdlrenderer.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "src/live/face_module.h"
#include "src/live/present.h"
#include "src/live/window/window_view.h"

namespace infocus {

namespace {

using Clock = std::chrono::steady_clock;

// The longest the loop waits for a new state: events and the mouse answer within this.
constexpr auto kStateWait = std::chrono::milliseconds(15);
// The magnifier follows the mouse at most this often, so a moving mouse does not flood the
// pipeline with crops it replaces at once.
constexpr auto kMagnifierPeriod = std::chrono::milliseconds(40);
// How long a control's error stays in the panel.
constexpr auto kErrorShown = std::chrono::seconds(4);
// Without a new state or an event the window is drawn again only this often: drawing is the
// window's whole cost, and in software (Xvfb, no GPU) it takes CPU from the analysis.
constexpr auto kIdleRedraw = std::chrono::milliseconds(250);
// A press and release closer than this (window pixels) is a click, not a drag.
constexpr float kClickSlop = 4.0f;
// Peaking's tint, drawn where the mask marks (ARGB).
constexpr uint32_t kPeakingArgb = 0xFFFF2020;
constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

std::string sdlError(const char* what) {
    return std::string(what) + " failed: " + SDL_GetError();
}

Error noWindow(const std::string& why) {
    return Error{ErrorKind::Unsupported,
                 "cannot open a window (" + why +
                     "); on a terminal use --ui tui, or serve the view to a browser with --ui web",
                 0};
}

// SDL, its window, renderer and ImGui context for the guard's lifetime, released in reverse on
// every way out.
class Display {
public:
    Display() = default;
    Display(const Display&) = delete;
    Display& operator=(const Display&) = delete;

    Status open() {
        if (Status st = windowDisplayCheck(); !st) return st;
        sdl_ = true;
        SDL_DisplayMode mode{};
        int w = 1600, h = 1000;
        if (SDL_GetDesktopDisplayMode(0, &mode) == 0) {
            w = std::min(w, mode.w);
            h = std::min(h, mode.h);
        }
        window_ = SDL_CreateWindow("infocus live", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                   w, h, SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
        if (!window_) return noWindow(sdlError("SDL_CreateWindow"));
        SDL_SetWindowMinimumSize(window_, 640, 480);
        // Linear filtering: the picture is usually shown smaller than the frame.
        SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "1");
        renderer_ = SDL_CreateRenderer(window_, -1, SDL_RENDERER_ACCELERATED);
        if (!renderer_) renderer_ = SDL_CreateRenderer(window_, -1, 0);
        if (!renderer_) return noWindow(sdlError("SDL_CreateRenderer"));

        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        imgui_ = true;
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        ImGui::StyleColorsDark();
        // DejaVu where installed (it has the arrows, µ, ∞ and × the panel uses), else ImGui's own.
        static const ImWchar ranges[] = {0x0020, 0x00FF, 0x2013, 0x2026, 0x2190,
                                         0x2193, 0x221E, 0x221E, 0};
        if (std::FILE* f = std::fopen(kFontPath, "rb")) {
            std::fclose(f);
            io.Fonts->AddFontFromFileTTF(kFontPath, 15.0f, nullptr, ranges);
            bigFont_ = io.Fonts->AddFontFromFileTTF(kFontPath, 52.0f, nullptr, ranges);
        } else {
            io.Fonts->AddFontDefault();
        }
        ImGui_ImplSDL2_InitForSDLRenderer(window_);
        ImGui_ImplSDLRenderer_Init(renderer_);
        backends_ = true;
        return {};
    }

    ~Display() {
        for (SDL_Texture* t : {picture_.texture, peaking_.texture, magnifier_.texture})
            if (t) SDL_DestroyTexture(t);
        if (backends_) {
            ImGui_ImplSDLRenderer_Shutdown();
            ImGui_ImplSDL2_Shutdown();
        }
        if (imgui_) ImGui::DestroyContext();
        if (renderer_) SDL_DestroyRenderer(renderer_);
        if (window_) SDL_DestroyWindow(window_);
        if (sdl_) SDL_Quit();
    }

    // A texture of one size and format, made again when either changes.
    struct Texture {
        SDL_Texture* texture = nullptr;
        int w = 0, h = 0;
        uint32_t format = 0;
    };

    // Makes @p t a streaming @p w × @p h texture of @p format; false if SDL cannot.
    bool ensure(Texture& t, int w, int h, uint32_t format) {
        if (t.texture && t.w == w && t.h == h && t.format == format) return true;
        if (t.texture) SDL_DestroyTexture(t.texture);
        t = Texture{SDL_CreateTexture(renderer_, format, SDL_TEXTUREACCESS_STREAMING, w, h), w, h,
                    format};
        return t.texture != nullptr;
    }

    // Uploads a luma plane as the Y of an IYUV texture with neutral chroma: the renderer turns
    // it into grey, so the CPU copies the plane once and converts nothing.
    bool uploadLuma(Texture& t, const Image<uint8_t>& luma) {
        if (!ensure(t, luma.width(), luma.height(), SDL_PIXELFORMAT_IYUV)) return false;
        const int cw = (luma.width() + 1) / 2, ch = (luma.height() + 1) / 2;
        if (chroma_.size() < static_cast<size_t>(cw) * ch) chroma_.assign(size_t(cw) * ch, 128);
        return SDL_UpdateYUVTexture(t.texture, nullptr, luma.data(), luma.width(), chroma_.data(),
                                    cw, chroma_.data(), cw) == 0;
    }

    // Uploads the peaking mask as a tint where it marks and transparency elsewhere.
    bool uploadPeaking(const Image<uint8_t>& mask) {
        if (!ensure(peaking_, mask.width(), mask.height(), SDL_PIXELFORMAT_ARGB8888)) return false;
        SDL_SetTextureBlendMode(peaking_.texture, SDL_BLENDMODE_BLEND);
        void* pixels = nullptr;
        int pitch = 0;
        if (SDL_LockTexture(peaking_.texture, nullptr, &pixels, &pitch) != 0) return false;
        for (int y = 0; y < mask.height(); ++y) {
            const uint8_t* in = mask.row(y);
            auto* out = reinterpret_cast<uint32_t*>(static_cast<uint8_t*>(pixels) + y * pitch);
            for (int x = 0; x < mask.width(); ++x)
                out[x] = in[x] ? kPeakingArgb : 0u;
        }
        SDL_UnlockTexture(peaking_.texture);
        return true;
    }

    SDL_Window* window_ = nullptr;
    SDL_Renderer* renderer_ = nullptr;
    ImFont* bigFont_ = nullptr;
    Texture picture_, peaking_, magnifier_;

private:
    bool sdl_ = false, imgui_ = false, backends_ = false;
    std::vector<uint8_t> chroma_;
};

// The frame rectangle between two frame points, clamped to the frame.
Rect rectBetween(std::array<float, 2> a, std::array<float, 2> b, int w, int h) {
    const int x0 = std::clamp(static_cast<int>(std::floor(std::min(a[0], b[0]))), 0, w);
    const int y0 = std::clamp(static_cast<int>(std::floor(std::min(a[1], b[1]))), 0, h);
    const int x1 = std::clamp(static_cast<int>(std::ceil(std::max(a[0], b[0]))), 0, w);
    const int y1 = std::clamp(static_cast<int>(std::ceil(std::max(a[1], b[1]))), 0, h);
    return Rect{x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

Status windowDisplayCheck() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wayland || !*wayland))
        return noWindow("neither DISPLAY nor WAYLAND_DISPLAY is set");
    // Video stays initialised for runWindow: SDL 2.26 fails to start X11 a second time in a
    // process that quit it. SDL_Quit at the end of runWindow, or at exit, releases it.
    if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) return noWindow(sdlError("SDL_Init"));
    // Without a usable display SDL falls back to drivers that show nothing.
    const char* driver = SDL_GetCurrentVideoDriver();
    const char* asked = std::getenv("SDL_VIDEODRIVER");
    if (driver && (!std::strcmp(driver, "offscreen") || !std::strcmp(driver, "dummy")) &&
        !(asked && !std::strcmp(asked, driver))) {
        SDL_QuitSubSystem(SDL_INIT_VIDEO);
        return noWindow("SDL found no usable display, only its " + std::string(driver) + " driver");
    }
    return {};
}

namespace {

// One window session: the events of a person, the newest state, and the drawing, each a stage.
class WindowLoop {
public:
    WindowLoop(Display& d, LiveView& view) : d_(d), view_(view) {
        notes_.bigFont = d.bigFont_;
        if (SDL_RendererInfo info{}; SDL_GetRendererInfo(d.renderer_, &info) == 0)
            notes_.renderer = info.name;
    }

    Status run(const RunLimits& limits) {
        const RunClock clock(limits);
        for (;;) {
            if (clock.done(state_.get())) return {};
            if (view_.ended()) return view_.endStatus();
            // Events first: keys and the mouse act on the picture drawn last.
            bool dirty = false;
            SDL_Event e;
            while (SDL_PollEvent(&e)) {
                dirty = true;
                if (!handle(e)) return {};
            }
            const std::optional<uint64_t> after =
                state_ ? std::optional(state_->frame) : std::nullopt;
            if (auto newer = view_.waitForState(after, kStateWait)) {
                state_ = newer;
                dirty = true;
            }
            if (!notes_.status.empty() && Clock::now() >= errorUntil_) notes_.status.clear();
            if (!dirty && Clock::now() - lastDraw_ < kIdleRedraw) continue;
            lastDraw_ = Clock::now();
            draw();
        }
    }

private:
    void control(const Status& st) {
        if (st) return;
        notes_.status = st.error().message;
        errorUntil_ = Clock::now() + kErrorShown;
    }

    // Acts on one event; false when it closes the window.
    bool handle(const SDL_Event& e) {
        ImGui_ImplSDL2_ProcessEvent(&e);
        const ImGuiIO& io = ImGui::GetIO();
        switch (e.type) {
            case SDL_QUIT:
                return false;
            case SDL_WINDOWEVENT:
                return e.window.event != SDL_WINDOWEVENT_CLOSE;
            case SDL_KEYDOWN:
                return key(e.key.keysym);
            case SDL_MOUSEWHEEL:
                if (!io.WantCaptureMouse && e.wheel.y != 0)
                    control(present::apply(
                        e.wheel.y > 0 ? present::Action::FocusUp : present::Action::FocusDown,
                        view_, state_.get()));
                break;
            case SDL_MOUSEBUTTONDOWN:
                if (e.button.button == SDL_BUTTON_LEFT && !io.WantCaptureMouse && state_ &&
                    pic_.contains(e.button.x, e.button.y)) {
                    dragFromWindow_ = {float(e.button.x), float(e.button.y)};
                    dragFrom_ = dragTo_ = pic_.toFrame(e.button.x, e.button.y);
                }
                break;
            case SDL_MOUSEMOTION:
                if (dragFrom_) dragTo_ = pic_.toFrame(e.motion.x, e.motion.y);
                break;
            case SDL_MOUSEBUTTONUP:
                if (e.button.button == SDL_BUTTON_LEFT && dragFrom_ && state_) endDrag(e.button);
                break;
            default:
                break;
        }
        return true;
    }

    // A key through the faces' shared map; false for quit.
    bool key(const SDL_Keysym& k) {
        const bool shift = (SDL_GetModState() & KMOD_SHIFT) != 0;
        present::Key named = present::Key::Char;
        if (k.sym == SDLK_LEFT) named = shift ? present::Key::ShiftLeft : present::Key::Left;
        if (k.sym == SDLK_RIGHT) named = shift ? present::Key::ShiftRight : present::Key::Right;
        if (k.sym == SDLK_ESCAPE) named = present::Key::Escape;
        const char ch = k.sym > 0 && k.sym < 128 ? static_cast<char>(k.sym) : 0;
        const present::Action action = present::actionForKey(named, ch);
        if (action == present::Action::Quit) return false;
        if (action == present::Action::ToggleMagnifier) zoom_ = zoom_ == 1 ? 2 : 1;
        control(present::apply(action, view_, state_.get()));
        return true;
    }

    // A drag scores the region it spans; a click (or a drag too thin to score) the whole frame.
    void endDrag(const SDL_MouseButtonEvent& b) {
        const float moved = std::hypot(b.x - (*dragFromWindow_)[0], b.y - (*dragFromWindow_)[1]);
        const Rect r =
            rectBetween(*dragFrom_, pic_.toFrame(b.x, b.y), state_->width, state_->height);
        control(view_.setScoreRoi(
            moved < kClickSlop || r.w < 4 || r.h < 4 ? std::nullopt : std::optional<Rect>(r)));
        dragFrom_.reset();
        dragTo_.reset();
        dragFromWindow_.reset();
    }

    // The magnifier follows the mouse over the picture, throttled; off the picture it hides.
    bool followMouse(int mx, int my) {
        const bool over = state_ && pic_.contains(mx, my) && !ImGui::GetIO().WantCaptureMouse &&
                          (SDL_GetWindowFlags(d_.window_) & SDL_WINDOW_MOUSE_FOCUS);
        std::optional<std::array<int, 3>> wanted;
        if (over) {
            const auto f = pic_.toFrame(mx, my);
            wanted = std::array<int, 3>{int(f[0]), int(f[1]), zoom_};
        }
        if (wanted != sentMagnifier_ && Clock::now() - lastMagnifier_ >= kMagnifierPeriod) {
            control(view_.setMagnifier(wanted));
            sentMagnifier_ = wanted;
            lastMagnifier_ = Clock::now();
        }
        return over;
    }

    // The pictures: uploaded once per state, the same textures drawn until the next.
    bool upload() {
        const LiveState* s = state_.get();
        if (s && s->preview && s->frame != shownPicture_) {
            d_.uploadLuma(d_.picture_, *s->preview);
            shownPicture_ = s->frame;
        }
        const bool peaking = s && s->peakingMask && s->peaking != PeakingMode::Off;
        if (peaking && s->frame != shownPeaking_) {
            d_.uploadPeaking(*s->peakingMask);
            shownPeaking_ = s->frame;
        }
        if (s && s->magnifier && s->magnifier->crop.data() && s->frame != shownMagnifier_) {
            d_.uploadLuma(d_.magnifier_, s->magnifier->crop);
            shownMagnifier_ = s->frame;
        }
        return peaking;
    }

    void draw() {
        // The layout: the picture letterboxed left of the panel.
        int ww = 0, wh = 0, lw = 0, lh = 0;
        SDL_GetRendererOutputSize(d_.renderer_, &ww, &wh);
        SDL_GetWindowSize(d_.window_, &lw, &lh);
        if (state_)
            pic_ = window::letterbox(state_->width, state_->height,
                                     std::max(1.0f, lw - window::kPanelWidth), float(lh));
        int mx = 0, my = 0;
        SDL_GetMouseState(&mx, &my);
        const bool over = followMouse(mx, my);
        const bool peaking = upload();

        ImGui_ImplSDLRenderer_NewFrame();
        ImGui_ImplSDL2_NewFrame();
        ImGui::NewFrame();
        if (state_) {
            window::OverlayNotes overlay;
            if (dragFrom_ && dragTo_)
                overlay.dragRoi = rectBetween(*dragFrom_, *dragTo_, state_->width, state_->height);
            if (over && sentMagnifier_) {
                overlay.mouse = std::array<float, 2>{float(mx), float(my)};
                overlay.magnifierTexture = d_.magnifier_.texture;
            }
            window::drawOverlays(*ImGui::GetBackgroundDrawList(), *state_, pic_, overlay);
        }
        const Clock::time_point drawnAt = Clock::now();
        drawn_.push_back(drawnAt);
        while (drawn_.size() > 2 && drawn_.front() < drawnAt - std::chrono::seconds(1))
            drawn_.pop_front();
        const double span = std::chrono::duration<double>(drawn_.back() - drawn_.front()).count();
        notes_.drawFps = span > 0 ? (drawn_.size() - 1) / span : 0.0;
        notes_.magnifierZoom = zoom_;
        window::drawPanel(state_.get(), notes_, float(lw), float(lh));
        ImGui::Render();

        SDL_SetRenderDrawColor(d_.renderer_, 18, 18, 22, 255);
        SDL_RenderClear(d_.renderer_);
        if (state_ && d_.picture_.texture && shownPicture_ != UINT64_MAX) {
            // Window coordinates to output pixels (they differ on a high-DPI display).
            const float sx = lw > 0 ? float(ww) / lw : 1.0f, sy = lh > 0 ? float(wh) / lh : 1.0f;
            const SDL_Rect dst{int(pic_.x * sx), int(pic_.y * sy), int(std::lround(pic_.w * sx)),
                               int(std::lround(pic_.h * sy))};
            SDL_RenderCopy(d_.renderer_, d_.picture_.texture, nullptr, &dst);
            if (peaking && d_.peaking_.texture)
                SDL_RenderCopy(d_.renderer_, d_.peaking_.texture, nullptr, &dst);
        }
        ImGui_ImplSDLRenderer_RenderDrawData(ImGui::GetDrawData());
        SDL_RenderPresent(d_.renderer_);
    }

    Display& d_;
    LiveView& view_;
    std::shared_ptr<const LiveState> state_;
    window::PanelNotes notes_;
    window::PictureRect pic_;
    Clock::time_point errorUntil_ = Clock::now(), lastMagnifier_ = Clock::now(),
                      lastDraw_ = Clock::now();
    uint64_t shownPicture_ = UINT64_MAX, shownPeaking_ = UINT64_MAX, shownMagnifier_ = UINT64_MAX;
    std::deque<Clock::time_point> drawn_;  // the last second's draws, for the drawn rate
    int zoom_ = 1;
    std::optional<std::array<int, 3>> sentMagnifier_;
    std::optional<std::array<float, 2>> dragFrom_, dragTo_;  // frame pixels
    std::optional<std::array<float, 2>> dragFromWindow_;
};

// The window as a face: a display is checked before the camera opens, the picture kept at full
// size; no window after all (SDL_CreateWindow failed) is a usage error, like no display.
class WindowFace final : public Face {
public:
    Status prepare(LiveOptions& options) override {
        if (Status st = windowDisplayCheck(); !st)
            return makeError(ErrorKind::Usage, st.error().message);
        options.previewLongSide = std::max(options.previewLongSide, kWindowPreviewLongSide);
        return {};
    }
    Status run(LiveView& view, const RunLimits& limits) override {
        Status st = runWindow(view, limits);
        if (!st && st.error().kind == ErrorKind::Unsupported && !view.ended())
            return makeError(ErrorKind::Usage, st.error().message);
        return st;
    }
};

}  // namespace

Status runWindow(LiveView& view, const RunLimits& limits) {
    Display d;
    if (Status st = d.open(); !st) return st;
    return WindowLoop(d, view).run(limits);
}

}  // namespace infocus

extern "C" __attribute__((visibility("default"))) const infocus::FaceModule* infocus_window_face() {
    static const infocus::FaceModule table{
        infocus::kFaceModuleAbi,
        [](const infocus::FaceSettings&) -> infocus::Face* { return new infocus::WindowFace(); }};
    return &table;
}
