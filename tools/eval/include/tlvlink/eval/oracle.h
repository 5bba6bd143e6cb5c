#pragma once
// Ceilings of the touch tasks on a simulated set, from what the simulator recorded about each
// sample (its sidecar; a set without one has no oracle). Two rows per task:
//
//   hidden  the best prediction from the simulator's hidden variables. hard/soft and
//           rough/smooth are functions of them (E > 1 MPa; Sq > 5 um rough, <= 1 um smooth:
//           tlvlink/sim/materials.h), so their oracle is 100 %. Material is not: its oracle is
//           the Bayes-optimal class given the recorded (E, nu, mu, Sq, lc, H) under the
//           generator's prior (classes equally likely; E and Sq log-uniform, the others
//           uniform, each inside its class range; the layer thickness is not recorded and is
//           marginalised).
//   frame   an estimate of how much of that one frame can carry: a k-nearest-neighbour vote
//           (kFrameOracleNeighbours, features standardised on the training split), fitted on
//           the training split and scored on the test split, on the physical quantities a
//           frame shows: the normal force (the gel is a calibrated spring: its imprint volume
//           reads the load), the contact area, the deepest gel indentation, and the texture as
//           the gel takes it (texture_kappa * Sq): its shading contrast and, when that contrast
//           clears the camera noise (oracle.cc kVisibleTextureDn), its correlation length and
//           Hurst exponent. Not E or kappa: a frame shows only the gel's surface. A k-NN estimate
//           approaches the Bayes rate of those features with many samples and is below it with
//           few; frames show the features with noise, so a model can fall short of it, and they
//           also show what the features leave out (shape details), so a model may exceed it.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/eval/tasks.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::eval {

inline constexpr int32_t kFrameOracleNeighbours = 15;

struct TouchOracle {
  Task task = Task::kMaterial;
  bool available = false;
  double hidden_accuracy = 0;  // on the labelled test items
  double frame_accuracy = 0;
  int64_t n = 0;     // labelled test items scored
  std::string note;  // why not available
};

// One oracle per touch task (kMaterial, kHard, kRough) on `touch`'s test split. Items without
// recorded hidden variables (class_id -1) are left out; a set without any gives unavailable
// results with a note.
std::vector<TouchOracle> touch_oracles(const TouchEmbeddings& touch);

// The Bayes-optimal material class of one recorded material (uniform class prior; the
// likelihood of each class is the product of the parameters' densities inside its ranges).
// Ties between classes are resolved toward the lower id; `tied` receives how many classes
// share the maximum (0 when no class admits the parameters).
int32_t bayes_material_class(const sim::MaterialSample& m, int32_t* tied = nullptr);

// k-nearest-neighbour vote: `train` and `query` are row-major [rows, dims] features,
// standardised by the training rows' mean and std; ties in the vote go to the class whose
// voters are nearer in total. Labels are 0..classes-1. Returns one prediction per query row.
std::vector<int32_t> knn_predict(std::span<const double> train, std::span<const int32_t> labels,
                                 std::span<const double> query, int32_t dims, int32_t classes,
                                 int32_t k);

// For each row index in `queries`: the share of each material class among its k nearest rows
// of another group (features standardised over all rows; the query's own group, i.e. its own
// object, is never a neighbour). classes[i] in 0..kMaterialClassCount-1.
std::vector<std::array<double, sim::kMaterialClassCount>> knn_class_weights_other_groups(
    std::span<const double> rows, std::span<const int32_t> classes,
    std::span<const std::string> groups, std::span<const size_t> queries, int32_t dims, int32_t k);

// The grasp task's counterpart of the touch tasks' one-frame estimate: how much of the grasp
// oracle the frames a grasp head receives (both fingers' "during" frames) can carry. The grasp
// oracle sees the friction coefficient itself; a frame shows it only through the material it
// recognises. So, on the test split:
//   frames       P(success) with the grip force and the contact areas as recorded (a frame
//                shows both: the gel is a calibrated spring) and mu marginalised over the
//                material classes a k-NN vote gives from both fingers' frame features (the touch
//                estimate's: force, contact area, gel depth, the texture the gel shows), each
//                class's mu over its range. The vote's neighbours are every other object's
//                episodes (both splits; never the episode's own object).
//   class        the same with the true class (mu via class only), on the same episodes.
// Generous where frames are noisy (force and areas exact) and short where they show more than
// the features (a better material reader would do better), like the touch estimate.
struct GraspFramesOracle {
  bool available = false;
  double frames_accuracy = 0, class_accuracy = 0, majority_rate = 0;
  int64_t n = 0;     // test episodes scored (with recorded variables)
  std::string note;  // why not available
};
Result<GraspFramesOracle> grasp_frames_oracle(const GraspEmbeddings& grasp);

}  // namespace tlvlink::eval
