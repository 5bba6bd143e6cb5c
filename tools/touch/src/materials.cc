// The Touch-and-Go material table. Ranges are plausible magnitudes for what a GelSight press
// meets (literature moduli, profilometer-scale Sq, elastomer-on-X friction), chosen so that the
// physics labels agree with TAG's class labels: the soft classes {leather, synthetic fabric,
// natural fabric, paper, grass} stay at or below 1 MPa (what the gel feels is the compliant
// surface layer or the stack, not the fibre modulus) and every hard class starts above it.
// Rough/smooth is left to the sampled Sq: most classes straddle one threshold. Thin soft layers
// (fabric, leather, paper, turf) and rubber mats carry a layer thickness: what the gel presses is
// that layer on a rigid backing, so it, not the object radius, sets the compliance split.

#include "tlvlink/touch/materials.h"

namespace tlvlink::touch {
namespace {

using S = std::array<double, kPressShapeCount>;  // sphere, cylinder, flat, edge

// clang-format off
constexpr MaterialClass kClasses[kMaterialClassCount] = {
  // id name              modulus Pa     poisson      friction     Sq um          corr. mm     hurst       colour           jit pattern    TAGhard effus. shapes (sph, cyl, flat, edge) layer mm
  {0,  "concrete",        {2e10, 4e10},  {.15, .25},  {.60, .90},  {8, 80},       {.3, 2.0},   {.70, .90}, {150, 150, 146}, 25, "speckle", true,  1800,  S{.2, .1, .5, .2}, {0, 0}},
  {1,  "plastic",         {5e8, 4e9},    {.35, .42},  {.25, .50},  {.05, 8},      {.05, .5},   {.60, .90}, {60, 110, 190},  90, "plain",   true,  600,   S{.3, .3, .2, .2}, {0, 0}},
  {2,  "glass",           {5e10, 9e10},  {.20, .25},  {.20, .45},  {.002, .3},    {.02, .3},   {.80, 1.0}, {185, 205, 210}, 15, "glossy",  true,  1400,  S{.2, .4, .3, .1}, {0, 0}},
  {3,  "wood",            {5e9, 1.5e10}, {.30, .45},  {.35, .60},  {1, 25},       {.1, 1.5},   {.50, .80}, {150, 105, 65},  30, "grain",   true,  400,   S{.1, .2, .4, .3}, {0, 0}},
  {4,  "metal",           {7e10, 2.1e11},{.27, .34},  {.15, .45},  {.02, 3},      {.02, .3},   {.70, .90}, {165, 168, 172}, 20, "brushed", true,  12000, S{.2, .3, .2, .3}, {0, 0}},
  {5,  "brick",           {5e9, 2e10},   {.15, .20},  {.60, .90},  {15, 120},     {.3, 2.5},   {.60, .85}, {165, 75, 55},   25, "bricks",  true,  1100,  S{.1, 0, .6, .3}, {0, 0}},
  {6,  "tile",            {2e10, 7e10},  {.20, .30},  {.30, .60},  {.05, 8},      {.05, .5},   {.70, .90}, {205, 200, 190}, 30, "tiles",   true,  1300,  S{0, 0, .7, .3}, {0, 0}},
  {7,  "leather",         {1e5, 1e6},    {.40, .49},  {.50, .90},  {.3, 15},      {.1, 1.0},   {.60, .90}, {110, 70, 45},   30, "pores",   false, 400,   S{.4, .2, .4, 0}, {.8, 3}},
  {8,  "synthetic fabric",{1e4, 3e5},    {.30, .45},  {.40, .80},  {1, 40},       {.1, .8},    {.50, .80}, {80, 80, 150},   80, "weave",   false, 150,   S{.4, .1, .5, 0}, {.3, 3}},
  {9,  "natural fabric",  {1e4, 3e5},    {.30, .45},  {.50, .90},  {3, 80},       {.1, 1.0},   {.40, .80}, {200, 190, 170}, 50, "weave",   false, 200,   S{.4, .1, .5, 0}, {.3, 4}},
  {10, "rubber",          {1.5e6, 2e7},  {.46, .49},  {.80, 1.20}, {.3, 20},      {.1, 1.0},   {.60, .90}, {40, 40, 42},    20, "plain",   true,  500,   S{.3, .3, .3, .1}, {1, 10}},
  {11, "paper",           {5e4, 8e5},    {.20, .35},  {.35, .60},  {.3, 8},       {.05, .4},   {.50, .80}, {235, 232, 220}, 15, "fibres",  false, 300,   S{0, .1, .6, .3}, {.1, 5}},
  {12, "tree",            {2e8, 3e9},    {.30, .40},  {.60, 1.00}, {40, 300},     {.8, 5.0},   {.40, .70}, {95, 75, 55},    25, "bark",    true,  500,   S{.2, .5, .3, 0}, {0, 0}},
  {13, "grass",           {2e4, 5e5},    {.30, .45},  {.40, .80},  {30, 300},     {.5, 3.0},   {.30, .60}, {70, 140, 50},   30, "blades",  false, 1000,  S{.4, 0, .6, 0}, {5, 30}},
  {14, "soil",            {2e6, 5e7},    {.30, .40},  {.50, .90},  {20, 200},     {.2, 2.0},   {.40, .70}, {100, 75, 50},   25, "clumps",  true,  1200,  S{.4, 0, .6, 0}, {0, 0}},
  {15, "rock",            {1e10, 7e10},  {.20, .30},  {.50, .90},  {5, 150},      {.3, 4.0},   {.60, .85}, {130, 125, 118}, 30, "mottled", true,  2500,  S{.5, 0, .3, .2}, {0, 0}},
  {16, "gravel",          {1e9, 3e10},   {.20, .30},  {.60, .90},  {50, 400},     {1.0, 5.0},  {.50, .80}, {140, 135, 125}, 30, "cells",   true,  1500,  S{.8, 0, .2, 0}, {0, 0}},
  {17, "sand",            {5e6, 1e8},    {.25, .35},  {.50, .80},  {10, 100},     {.1, .6},    {.50, .70}, {210, 185, 140}, 20, "speckle", true,  1100,  S{.3, 0, .7, 0}, {0, 0}},
  {18, "plants",          {5e6, 1e8},    {.30, .45},  {.40, .80},  {.3, 20},      {.1, 1.0},   {.50, .80}, {60, 120, 45},   35, "veins",   true,  1000,  S{.3, .3, .4, 0}, {0, 0}},
  {19, "others",          {2e6, 5e10},   {.25, .45},  {.30, .80},  {.1, 60},      {.05, 2.0},  {.50, .90}, {128, 128, 128}, 90, "patches", true,  700,   S{.25, .25, .25, .25}, {0, 0}},
};
// clang-format on

}  // namespace

std::span<const MaterialClass> material_classes() { return kClasses; }

Result<const MaterialClass*> material_class(int32_t id) {
  TLV_ENSURE(id >= 0 && id < kMaterialClassCount, ErrorCode::kInvalidArgument,
             "material class id %d is outside 0..%d", id, kMaterialClassCount - 1);
  return &kClasses[id];
}

const MaterialClass* find_material_class(std::string_view name) {
  for (const MaterialClass& c : kClasses) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

ThermalFeel thermal_feel(const MaterialClass& c) {
  if (c.thermal_effusivity >= kCoolEffusivity) return ThermalFeel::kCool;
  if (c.thermal_effusivity <= kWarmEffusivity) return ThermalFeel::kWarm;
  return ThermalFeel::kNeutral;
}

}  // namespace tlvlink::touch
