// SPDX-License-Identifier: MIT
/// @file sim.h
/// The simulated camera `sim:`: textured scenes at known depths rendered through a thin lens,
/// whose PSF is the uniform defocus disc convolved with a diffraction core, and its ground truth
/// (true depth, true blur width, true in-focus distance) for tests that check measurements
/// against it.
///
/// Source string options (all optional):
///   scene=plane|steps|tilted|edges   what is in front of the camera (default plane)
///   focus=1.2m | focus=0.8dpt | focus=inf   in-focus distance from the lens, or dioptres
///   distance=1m          plane/tilted/edges: distance of the plane (on the optical axis)
///   distances=0.3m:0.6m:1.2m:2.4m   steps: the planes' distances, left to right
///   tilt=30 axis=x|y     tilted: angle in degrees about the image's x (depth varies down the
///                        image) or y axis (depth varies across it)
///   angle=5              edges: slant of the chart's squares in degrees
///   size=1280x720 fps=30 noise=0.01 seed=1 format=GREY|YUYV pace=camera|fast
///   focal=4.74mm fnumber=1.8 pitch=1.4um sensor=4608x2592   the lens and full-resolution sensor
///   travel=20ms settle=10ms   the lens's time to cross its range (0–10 dpt) and to settle
///   delay=2              frames between a frame's exposure and its delivery
///   move=0.5m:4s         plane/tilted/edges: the distance goes from distance= to 0.5 m over 4 s
///                        of frame time (linearly in metres), then holds
/// The default lens is a Raspberry Pi Camera Module 3. The output image is the full sensor scaled
/// to `size`, so the pixel pitch is pitch × sensor width / output width.
///
/// The PSF is the defocus disc of diameter ΔX_i = A·|z_s(1/f − 1/z_o) − 1| (optics::blurWidth)
/// convolved with a Gaussian of σ = 0.42·λ·N, λ = 550 nm, the usual fit to the core of the Airy
/// pattern (Airy disc diameter 2.44·λ·N). The texture holds each pixel's area average of the
/// sharp scene (the sensor's pixel integration) and is blurred as a continuous image (cubic
/// interpolation that adds no blur), so defocus far below a pixel still softens the image and a
/// focus measure rises and falls smoothly through focus.
///
/// Time is the frames' own: frame k is exposed at k/fps, so lens travel, settling and the moving
/// plane do not depend on the machine's speed. A move asked for after frame k is delivered starts
/// at the exposure of frame k + delay, and each frame's lens position is the one at its exposure.
///
/// render() gathers discs of 2·kSimFastMinHalfDiscPx output pixels and wider on a texture of
/// half, a quarter or an eighth of the output's resolution, with the disc narrowed to keep the
/// PSF's variance, and interpolates back (renderExact() gathers everything at full resolution).
///
/// Model limits (documented simplifications): the texture is fixed in image space (no change of
/// magnification with focus or depth); each output pixel is blurred with the PSF of its own
/// depth (a gather), which is exact inside a constant-depth region and approximate within one
/// blur radius of a depth step; disc diameters are rendered in steps of kSimDiameterStepPx
/// (a focus change smaller than that renders the same frame) and capped at kSimMaxDiameterPx;
/// diffraction is one wavelength and a Gaussian core (no Airy rings, no colour); the disc is
/// uniform (no aberrations, vignetting or cat's-eye shapes off axis); the texture itself is
/// sampled at the output pixels, so detail finer than a pixel is absent (no aliasing); the
/// cubic's small negative lobes can overshoot a sharp edge slightly under sub-pixel blur.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"
#include "infocus/lens_presets.h"
#include "infocus/optics.h"

namespace infocus {

/// Rendered disc diameters are quantised to this step (pixels).
inline constexpr double kSimDiameterStepPx = 1.0 / 16.0;
/// Largest disc diameter rendered (pixels); larger blur is clipped to it.
inline constexpr double kSimMaxDiameterPx = 64.0;
/// The fast render reduces a disc's resolution only as far as it stays this wide (pixels).
inline constexpr double kSimFastMinDiscPx = 6.0;
/// ... and at half resolution, this wide (pixels of the half-resolution texture).
inline constexpr double kSimFastMinHalfDiscPx = 4.0;
/// Wavelength of the simulated light, for the diffraction core: green, 550 nm.
inline constexpr double kSimWavelengthM = optics::kDefaultWavelength;

/// A thin lens in front of a sensor.
struct SimLens {
    /// The default lens: the rpi-cam3 preset (lens_presets.h).
    SimLens();
    /// The lens and sensor of @p preset (a preset without a sensor leaves pitch and size 0).
    explicit SimLens(const optics::LensPreset& preset);

    double focalLengthM = 0.0;       ///< f
    double fNumber = 0.0;            ///< N
    double sensorPixelPitchM = 0.0;  ///< pixel pitch at full sensor resolution
    Size sensorSize;                 ///< full sensor resolution, pixels

    /// The lens as the optics model sees it.
    optics::ThinLens thinLens() const { return {focalLengthM, fNumber}; }
    /// Aperture diameter A = f/N, metres.
    double apertureM() const { return thinLens().aperture(); }
    /// Pixel pitch of an image of @p widthPx covering the whole sensor, metres.
    double pixelPitchM(int widthPx) const { return sensorPixelPitchM * sensorSize.width / widthPx; }
};

/// The thin-lens disc diameter ΔX_i = A·|z_s(1/f − 1/z_o) − 1| on the sensor (metres) of a point
/// at @p depthM from the lens with the lens focused at @p focusDioptres (1/u; 0 is infinity):
/// optics::blurWidth at optics::sensorDistanceForFocus. nullopt when the focus is at or inside
/// the focal length or the depth is not positive.
std::optional<double> simBlurDiameterM(const SimLens& lens, double focusDioptres, double depthM);

/// The scenes of the simulated camera.
enum class SimScene { Plane, Steps, Tilted, Edges };

/// Axis a tilted plane turns about.
enum class SimAxis { X, Y };

/// Everything that defines a simulated camera.
struct SimConfig {
    SimScene scene = SimScene::Plane;
    SimLens lens;
    double focusDioptres = 1.0 / 1.2;        ///< in-focus distance 1.2 m
    std::vector<double> distancesM{1.0};     ///< one per plane; steps: several
    double tiltDeg = 30.0;                   ///< tilted scene
    SimAxis tiltAxis = SimAxis::X;           ///< tilted scene
    double edgeAngleDeg = 5.0;               ///< edges scene
    Size size{1280, 720};                    ///< output resolution
    double fps = 30.0;                       ///< frame rate, 1e-6..1e6 (timestamps and pacing)
    double noise = 0.0;                      ///< Gaussian noise σ, fraction of full scale
    uint64_t seed = 1;                       ///< texture and noise seed
    PixelFormat format = PixelFormat::GREY;  ///< GREY or YUYV (neutral chroma)
    bool paced = true;                       ///< deliver at fps like a camera; false: at once
    /// Time for the lens to cross its whole range (0–10 dpt), seconds: a voice-coil module with
    /// slew-rate control crosses it in tens of milliseconds.
    double lensTravelS = 0.02;
    /// Time for the lens to come to rest after its travel, seconds (a voice coil's ringing
    /// under ringing control: about one vibration period, 5–15 ms).
    double lensSettleS = 0.01;
    /// Frames between a frame's exposure and its delivery (an ISP's or a UVC camera's queue).
    int delayFrames = 2;
    /// The moving plane: distancesM[0] goes to @ref moveToM over @ref moveS seconds, then holds.
    /// Not set: the scene stands still.
    std::optional<double> moveToM;
    double moveS = 0.0;  ///< duration of the move, seconds (> 0 with moveToM)
};

/// The distance of the scene's (first) plane at @p timeS seconds: distancesM[0], or on the way
/// from it to moveToM, linearly in metres over moveS, then moveToM.
double simDistanceAtM(const SimConfig& config, double timeS);

/// Parses sim: options (listed above) into a config. Usage error naming the bad option.
Result<SimConfig> parseSimOptions(const std::map<std::string, std::string>& options);

/// A region of the image with a single (or central) depth and its true blur.
struct SimRegion {
    Rect rect;
    double depthM = 0.0;          ///< depth at the region's centre, metres from the lens
    double blurDiameterPx = 0.0;  ///< geometric ΔX_i at that depth, output pixels (uncapped)
};

/// Renders a scene; holds the ground truth. Deterministic for a given config.
class SimRenderer {
public:
    /// Builds the scene (texture rendered once). Usage error for an invalid config.
    static Result<std::unique_ptr<SimRenderer>> create(const SimConfig& config);
    ~SimRenderer();

    const SimConfig& config() const { return config_; }
    /// Depth of the scene point seen by output pixel (x, y), metres from the lens, at @p timeS.
    double depthAtM(int x, int y, double timeS = 0.0) const;
    /// True geometric blur diameter ΔX_i (the defocus disc alone, without diffraction) at pixel
    /// (x, y) for @p focusDioptres at @p timeS, output pixels.
    double blurDiameterPxAt(int x, int y, double focusDioptres, double timeS = 0.0) const;
    /// The diameter the renderer actually uses at (x, y): blurDiameterPxAt quantised to
    /// kSimDiameterStepPx and capped at kSimMaxDiameterPx.
    double renderedDiameterPxAt(int x, int y, double focusDioptres) const;
    /// Diameter of the Airy disc 2.44·λ·N in output pixels: the diffraction floor, the blur of a
    /// point in focus. The rendered PSF is the disc convolved with its Gaussian core.
    double airyDiameterPx() const;
    /// σ of the Gaussian core the renderer convolves the disc with, 0.42·λ·N, output pixels.
    double diffractionSigmaPx() const;
    /// The scene's regions: plane/edges one, steps one per plane, tilted a 16×9 grid.
    std::vector<SimRegion> regions(double focusDioptres, double timeS = 0.0) const;
    /// Factor on every depth at @p timeS: simDistanceAtM over distancesM[0].
    double depthScaleAt(double timeS) const;
    /// Distance from the lens that is in focus at @p focusDioptres (infinity for 0).
    static double inFocusDistanceM(double focusDioptres);
    /// The sharp (unblurred) scene as seen by the output pixels, grey levels 0..255.
    Image<float> sharpImage() const;
    /// Renders the scene blurred for @p focusDioptres at @p timeS, without noise, grey levels
    /// 0..255: the fast render (wide discs at reduced resolution).
    Image<float> render(double focusDioptres, double timeS = 0.0);
    /// The same with every pixel gathered at full resolution: the reference the fast render is
    /// held to. Slow for wide discs (about a second at 720p and 60 px).
    Image<float> renderExact(double focusDioptres, double timeS = 0.0);

private:
    SimRenderer() = default;
    struct Impl;
    SimConfig config_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace infocus
