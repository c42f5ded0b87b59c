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

Status runWindow(LivePipeline& pipeline, const WindowOptions& options) {
    Display d;
    if (Status st = d.open(); !st) return st;

    const Clock::time_point start = Clock::now();
    Clock::time_point errorUntil = start, lastMagnifier = start, lastDraw = start;
    std::shared_ptr<const LiveState> state;
    uint64_t shownPicture = UINT64_MAX, shownPeaking = UINT64_MAX, shownMagnifier = UINT64_MAX;
    window::PanelNotes notes;
    notes.bigFont = d.bigFont_;
    if (SDL_RendererInfo info{}; SDL_GetRendererInfo(d.renderer_, &info) == 0)
        notes.renderer = info.name;
    std::deque<Clock::time_point> drawn;  // the last second's draws, for the drawn rate
    int zoom = 1;
    std::optional<std::array<int, 3>> sentMagnifier;
    std::optional<std::array<float, 2>> dragFrom, dragTo;  // frame pixels
    std::optional<std::array<float, 2>> dragFromWindow;
    window::PictureRect pic;

    auto control = [&](const Status& st) {
        if (st) return;
        notes.status = st.error().message;
        errorUntil = Clock::now() + kErrorShown;
    };
    auto focus = [&](int steps) {
        const bool shift = (SDL_GetModState() & KMOD_SHIFT) != 0;
        control(pipeline.focusStep(shift ? steps * 10 : steps));
    };

    for (;;) {
        if (options.stop && options.stop->load()) return {};
        const Clock::time_point now = Clock::now();
        if (options.seconds &&
            std::chrono::duration<double>(now - start).count() >= *options.seconds)
            return {};
        if (options.frames && state && state->frame + 1 >= *options.frames) return {};
        if (pipeline.ended()) return pipeline.endStatus();

        // Events first: keys and the mouse act on the picture drawn last.
        SDL_Event e;
        bool dirty = false;
        while (SDL_PollEvent(&e)) {
            dirty = true;
            ImGui_ImplSDL2_ProcessEvent(&e);
            const ImGuiIO& io = ImGui::GetIO();
            switch (e.type) {
                case SDL_QUIT:
                    return {};
                case SDL_WINDOWEVENT:
                    if (e.window.event == SDL_WINDOWEVENT_CLOSE) return {};
                    break;
                case SDL_KEYDOWN:
                    switch (e.key.keysym.sym) {
                        case SDLK_q:
                        case SDLK_ESCAPE:
                            return {};
                        case SDLK_LEFT:
                            focus(-1);
                            break;
                        case SDLK_RIGHT:
                            focus(1);
                            break;
                        case SDLK_a:
                            control(pipeline.autofocus());
                            break;
                        case SDLK_r:
                            pipeline.resetPeak();
                            break;
                        case SDLK_g:
                            if (state) {
                                const auto [cols, rows] =
                                    window::nextGrid(state->cols, state->rows);
                                control(pipeline.setGrid(cols, rows));
                            }
                            break;
                        case SDLK_p:
                            if (state)
                                control(pipeline.setPeaking(window::nextPeaking(state->peaking)));
                            break;
                        case SDLK_m:
                            zoom = zoom == 1 ? 2 : 1;
                            break;
                        default:
                            break;
                    }
                    break;
                case SDL_MOUSEWHEEL:
                    if (!io.WantCaptureMouse && e.wheel.y != 0) focus(e.wheel.y > 0 ? 1 : -1);
                    break;
                case SDL_MOUSEBUTTONDOWN:
                    if (e.button.button == SDL_BUTTON_LEFT && !io.WantCaptureMouse && state &&
                        pic.contains(e.button.x, e.button.y)) {
                        dragFromWindow = {float(e.button.x), float(e.button.y)};
                        dragFrom = dragTo = pic.toFrame(e.button.x, e.button.y);
                    }
                    break;
                case SDL_MOUSEMOTION:
                    if (dragFrom) dragTo = pic.toFrame(e.motion.x, e.motion.y);
                    break;
                case SDL_MOUSEBUTTONUP:
                    if (e.button.button == SDL_BUTTON_LEFT && dragFrom && state) {
                        const float moved = std::hypot(e.button.x - (*dragFromWindow)[0],
                                                       e.button.y - (*dragFromWindow)[1]);
                        const Rect r = rectBetween(*dragFrom, pic.toFrame(e.button.x, e.button.y),
                                                   state->width, state->height);
                        // A click clears the ROI; a drag too thin to score is a click too.
                        control(pipeline.setScoreRoi(moved < kClickSlop || r.w < 4 || r.h < 4
                                                         ? std::nullopt
                                                         : std::optional<Rect>(r)));
                        dragFrom.reset();
                        dragTo.reset();
                        dragFromWindow.reset();
                    }
                    break;
                default:
                    break;
            }
        }

        if (auto newer = pipeline.waitForState(state ? std::optional(state->frame) : std::nullopt,
                                               kStateWait)) {
            state = newer;
            dirty = true;
        }
        if (!notes.status.empty() && Clock::now() >= errorUntil) notes.status.clear();
        if (!dirty && Clock::now() - lastDraw < kIdleRedraw) continue;
        lastDraw = Clock::now();

        // The layout: the picture letterboxed left of the panel.
        int ww = 0, wh = 0;
        SDL_GetRendererOutputSize(d.renderer_, &ww, &wh);
        int lw = 0, lh = 0;
        SDL_GetWindowSize(d.window_, &lw, &lh);
        if (state)
            pic = window::letterbox(state->width, state->height,
                                    std::max(1.0f, lw - window::kPanelWidth), float(lh));

        // The magnifier follows the mouse over the picture, throttled; off the picture it hides.
        int mx = 0, my = 0;
        SDL_GetMouseState(&mx, &my);
        const bool over = state && pic.contains(mx, my) && !ImGui::GetIO().WantCaptureMouse &&
                          (SDL_GetWindowFlags(d.window_) & SDL_WINDOW_MOUSE_FOCUS);
        std::optional<std::array<int, 3>> wanted;
        if (over) {
            const auto f = pic.toFrame(mx, my);
            wanted = std::array<int, 3>{int(f[0]), int(f[1]), zoom};
        }
        if (wanted != sentMagnifier && Clock::now() - lastMagnifier >= kMagnifierPeriod) {
            control(pipeline.setMagnifier(wanted));
            sentMagnifier = wanted;
            lastMagnifier = Clock::now();
        }

        // The pictures: uploaded once per state, the same textures drawn until the next.
        if (state && state->preview && state->frame != shownPicture) {
            d.uploadLuma(d.picture_, *state->preview);
            shownPicture = state->frame;
        }
        const bool peaking = state && state->peakingMask && state->peaking != PeakingMode::Off;
        if (peaking && state->frame != shownPeaking) {
            d.uploadPeaking(*state->peakingMask);
            shownPeaking = state->frame;
        }
        if (state && state->magnifier && state->magnifier->crop.data() &&
            state->frame != shownMagnifier) {
            d.uploadLuma(d.magnifier_, state->magnifier->crop);
            shownMagnifier = state->frame;
        }

        ImGui_ImplSDLRenderer_NewFrame();
        ImGui_ImplSDL2_NewFrame();
        ImGui::NewFrame();
        if (state) {
            window::OverlayNotes overlay;
            if (dragFrom && dragTo)
                overlay.dragRoi = rectBetween(*dragFrom, *dragTo, state->width, state->height);
            if (over && sentMagnifier) {
                overlay.mouse = std::array<float, 2>{float(mx), float(my)};
                overlay.magnifierTexture = d.magnifier_.texture;
            }
            window::drawOverlays(*ImGui::GetBackgroundDrawList(), *state, pic, overlay);
        }
        const Clock::time_point drawnAt = Clock::now();
        drawn.push_back(drawnAt);
        while (drawn.size() > 2 && drawn.front() < drawnAt - std::chrono::seconds(1))
            drawn.pop_front();
        const double span = std::chrono::duration<double>(drawn.back() - drawn.front()).count();
        notes.drawFps = span > 0 ? (drawn.size() - 1) / span : 0.0;
        notes.magnifierZoom = zoom;
        window::drawPanel(state.get(), notes, float(lw), float(lh));
        ImGui::Render();

        SDL_SetRenderDrawColor(d.renderer_, 18, 18, 22, 255);
        SDL_RenderClear(d.renderer_);
        if (state && d.picture_.texture && shownPicture != UINT64_MAX) {
            // Window coordinates to output pixels (they differ on a high-DPI display).
            const float sx = lw > 0 ? float(ww) / lw : 1.0f, sy = lh > 0 ? float(wh) / lh : 1.0f;
            const SDL_Rect dst{int(pic.x * sx), int(pic.y * sy), int(std::lround(pic.w * sx)),
                               int(std::lround(pic.h * sy))};
            SDL_RenderCopy(d.renderer_, d.picture_.texture, nullptr, &dst);
            if (peaking && d.peaking_.texture)
                SDL_RenderCopy(d.renderer_, d.peaking_.texture, nullptr, &dst);
        }
        ImGui_ImplSDLRenderer_RenderDrawData(ImGui::GetDrawData());
        SDL_RenderPresent(d.renderer_);
    }
}

}  // namespace infocus
