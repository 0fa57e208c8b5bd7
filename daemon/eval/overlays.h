// Overlays of recognition results as PNG files (core/pictures/overlay.h draws them): the scene with
// each instance's model points, box and confidence, for `saccade recognize --render`, and an image
// of every case `saccade eval` missed or answered falsely, so a failing case can be seen at a
// glance.
#pragma once

#include "core/pictures/overlay.h"
#include "core/types.h"
#include "daemon/eval/evaluation.h"

#include <filesystem>
#include <string>
#include <vector>

namespace saccade {

/// Colours of the marks: the true pose, an instance within 8 cm of the truth, a false one.
inline constexpr Rgb kTruthColour{255, 210, 0};
inline constexpr Rgb kTrueColour{0, 230, 0};
inline constexpr Rgb kFalseColour{255, 40, 40};
/// Instances without a truth (recognize --render), in turn.
inline constexpr Rgb kInstanceColours[] = {
    {0, 230, 0}, {255, 0, 255}, {0, 220, 255}, {255, 140, 0}};

/// An instance's label: "#i 0.93" (its confidence), or "#i 12 VOTES" when it was not verified.
std::string InstanceLabel(std::size_t index, const Detection& d);

/// The scene as its camera saw it with `marks` drawn over it: the model's finite points and
/// its oriented box at each mark's pose. `camera` projects the model (and an unorganized
/// scene): for an organized scene, the intrinsics its points imply (EstimateIntrinsics).
RgbCanvas RenderOverlay(const Cloud& scene, const CameraIntrinsics& camera, const Cloud& model,
                        const std::vector<OverlayMark>& marks);

/// Writes `canvas` as an 8-bit RGB PNG. False with "PATH: reason" when it cannot; no file is
/// left at `path` then.
bool WriteOverlayPng(const std::string& path, const RgbCanvas& canvas, std::string* error);

namespace eval {

/// Writes `dir`/overlays/CASE-CONFIG.png for every scene where a configuration missed (a
/// feasible scene without a detection within 8 cm of the truth) or reported a false instance
/// (`trials` per configuration, then per scene, with the fovea on the truth). Each shows the
/// truth (the model at its true pose when the case has one, else a cross at the true centre)
/// and every instance, true ones and false ones in their colours (the 12 best ranked labelled,
/// the truth on top). Returns the number written, or -1 with `error` when a file cannot be
/// written.
int WriteCaseOverlays(const std::vector<EvalConfiguration>& configs,
                      const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                      const std::vector<std::vector<Trial>>& trials,
                      const std::filesystem::path& dir, std::string* error);

}  // namespace eval
}  // namespace saccade
