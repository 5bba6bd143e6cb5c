#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "model_constants.h is internal to tools/sim: include its public headers instead"
#endif
// Constants of the frame model (tools/sim/REFERENCE.md), in one place so each is named
// once with its reason. Lengths in mm, moduli in N/mm^2 (= MPa) inside the renderer.

#include <array>

namespace tlvlink::sim::internal {

// --- Mechanics -------------------------------------------------------------------------------
// Winkler layer p = chi * u_g * E*_g / t_g plus a membrane (Pasternak) tension term
// T = psi * E_g t_g / (6 (1 + nu_g)) acting on the positive curvature of the object inside the
// contact. Fitted (least squares in log depth, tests/sim/render/mechanics_test.cc) so a 20 mm
// sphere on the gelsight-r1.5 profile follows Taxim's R1.5 table: 0.18 mm @ 1.1 N,
// 0.38 mm @ 3.1 N, 0.58 mm @ 5.9 N (pure Winkler gives F ~ d^2, the table F ~ d^1.4).
inline constexpr double kChi = 3.27;
inline constexpr double kPsi = 5.1;
inline constexpr double kCalibrationSphereRadiusMm = 20.0;
// The membrane leaves the contact at the object's slope, but wraps a sharp edge only so far
// (it spreads over ~1 mm instead): |slope| <= 0.3 (17 deg) per pixel edge. The calibration
// sphere's slopes stay below it (a/R <= 0.24).
inline constexpr double kTensionMaxSlope = 0.3;
// Compliances C = (1 - nu^2) / E are clamped so kappa never divides by zero (1/Pa).
inline constexpr double kMinCompliancePerPa = 1e-15;
// Gel indentation never exceeds this fraction of the gel thickness.
inline constexpr double kMaxGelStrain = 0.9;
// A compliant layer on a rigid backing (fabric, leather, a paper stack, turf) compresses until
// its fibres jam: at most this share of its thickness. Fibre assemblies densify from ~0.1-0.2 to
// ~0.3-0.6 fibre volume fraction (van Wyk 1946), and fabric compression curves (Kawabata's
// KES-FB3) flatten out at 50-70 % strain. Beyond it the rest of the approach goes into the gel.
inline constexpr double kMaxLayerStrain = 0.6;
// The texture's own compliance split (texture_split) differs from the bulk one by less than this
// for stiff objects; such a texture is not rescaled: < 0.1 % of a texture is < 0.01 DN, and
// leaving it keeps their frames byte-identical to the renderer before the split existed.
inline constexpr double kTextureSplitTolerance = 1e-3;
// Force bisection: stop at |dF| < 1e-3 F or after 60 halvings; histogram bins of the gap.
inline constexpr double kForceRelTolerance = 1e-3;
inline constexpr int kMaxBisection = 60;
inline constexpr int kGapBins = 1024;

// --- Membrane spreading (Taxim-style) --------------------------------------------------------
// Gaussian scales (mm) for a 4 mm gel, scaled by t_g / 4 mm.
inline constexpr std::array<double, 6> kSpreadSigmasMm = {0.90, 0.46, 0.24, 0.10, 0.06, 0.03};
inline constexpr double kSpreadReferenceThicknessMm = 4.0;
inline constexpr double kCoreFraction = 0.4;  // core = u_tot > 0.4 max u_tot keeps its shape
inline constexpr double kMaxSlope = 2.5;      // |grad z| clamp (~68 deg)

// --- Optics ----------------------------------------------------------------------------------
inline constexpr double kDiffuse = 0.5;    // kd
inline constexpr double kSpecular = 0.25;  // ks
// The light amplitude is scaled so the strongest channel change at a 45 deg tilt is this many DN
// (Taxim's tables saturate near 40-80 DN at 30-60 deg); small-slope gain then is ~1.3 DN/deg.
inline constexpr double kMaxDeltaAt45Dn = 80.0;
inline constexpr double kPerLightGainSpread = 0.15;  // per-sensor LED gain +-15 %
inline constexpr double kWhiteBalanceSpread = 0.03;  // per-channel WB +-3 %
inline constexpr double kOverallGainSpread = 0.05;   // exposure gain 0.95-1.05

// --- Geometry --------------------------------------------------------------------------------
inline constexpr double kPointConeSlope = 1.7320508075688772;  // tan 60 deg: 30 deg half-angle
// Height where the object has no surface facing the gel (beyond a ball's equator, past a box
// edge): far below anything, so it never touches unless the press goes beyond kSurfaceGapLimitMm.
inline constexpr double kNoSurfaceMm = 1e6;
inline constexpr double kSurfaceGapLimitMm = 1e5;

// --- Texture ---------------------------------------------------------------------------------
inline constexpr int kMaxOctaves = 12;
inline constexpr double kMinWavelengthPx = 2.0;  // finer than 2 px is invisible (Nyquist)

// --- Markers and shear (FOTS / Cattaneo-Mindlin) ---------------------------------------------
// FOTS gives lambda in px^-2 on a 0.0634 mm/px sensor; converted to mm^-2 here.
inline constexpr double kDilationLambdaPerMm2 = 0.00125 / (0.0634 * 0.0634);
inline constexpr double kShearLambdaPerMm2 = 0.0003 / (0.0634 * 0.0634);
// Dilation coefficient (mm^-3): a 5 mm sphere 0.5 mm deep moves nearby markers ~0.2 mm outward.
inline constexpr double kDilationCoefficient = 0.15;
inline constexpr double kMaxDilationMm = 0.5;
// gamma in [0.2, 0.5]: the upper end, so the lag shows at a 2 mm marker pitch.
inline constexpr double kAnnulusLag = 0.5;
inline constexpr double kMaxShearStrain = 0.3;   // |rigid shift| <= 0.3 t_g: bounded gel shear
inline constexpr double kMaxTwistRad = 0.15;     // stick-region twist cap (~8.6 deg)
inline constexpr double kMaxSlipTwistRad = 0.5;  // imprint rotation in torsional gross slip
inline constexpr double kStiffnessFloor = 1e-9;  // k_t, k_theta floors (point contact)
inline constexpr double kSlipRatioCap = 1e6;     // rho when mu P == 0 but a load is applied
inline constexpr double kDeviationMm = 0.25;     // Dong-2019 analogue of 4 px @ 427x320
inline constexpr double kMarkerDepth = 0.85;     // marker centre transmits 15 % of the light
inline constexpr double kMarkerSigmaPerRadius = 0.6;

// --- Camera ----------------------------------------------------------------------------------
inline constexpr double kCameraBlurSigmaPx = 1.0;  // 5x5 blur
inline constexpr int kCameraBlurRadiusPx = 2;

}  // namespace tlvlink::sim::internal
