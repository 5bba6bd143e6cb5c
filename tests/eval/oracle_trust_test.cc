// Issue 16's evaluation additions on hand-made data: the touch oracles (Bayes material class
// from the recorded hidden variables, the k-NN one-frame estimate), and trust records written
// from a report into a model copy (zero-shot heads that do not beat the majority are dropped).

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/eval/eval.h"
#include "tlvlink/eval/oracle.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/head_trust.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/quantize/reference_encoder.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink {
namespace {

using eval::Method;
using eval::Task;

// The middle of every range of class `id`: only that class admits it... unless ranges overlap,
// which the test below accounts for by asking the oracle to pick the class with the densest
// prior there.
sim::MaterialSample centre_of(int32_t id) {
  const sim::MaterialClass& c = sim::material_classes()[static_cast<size_t>(id)];
  sim::MaterialSample m;
  m.class_id = id;
  auto mid = [](sim::Range r) { return 0.5 * (r.lo + r.hi); };
  auto geo = [](sim::Range r) { return std::sqrt(r.lo * r.hi); };
  m.modulus_pa = geo(c.modulus_pa);
  m.poisson = mid(c.poisson);
  m.friction = mid(c.friction);
  m.sq_um = geo(c.sq_um);
  m.correlation_length_mm = mid(c.correlation_length_mm);
  m.hurst = mid(c.hurst);
  m.hard = sim::hard_label(m.modulus_pa);
  m.rough = sim::rough_label(m.sq_um);
  return m;
}

TEST(Oracle, BayesMaterialClassOfEachClassCentre) {
  // Glass (2) and metal (4) are the only classes whose modulus reaches 7e10 with Sq below
  // 0.3 um; their centres are told apart by the others.
  int32_t right = 0;
  for (int32_t id = 0; id < sim::kMaterialClassCount; ++id) {
    int32_t ties = 0;
    const int32_t c = eval::bayes_material_class(centre_of(id), &ties);
    ASSERT_GE(c, 0) << "class " << id << "'s own centre must be admitted by some class";
    ASSERT_GE(ties, 1);
    right += c == id ? 1 : 0;
  }
  // Synthetic and natural fabric share most of their ranges; every other centre is unique.
  EXPECT_GE(right, 18);
  // Outside every range: no class.
  sim::MaterialSample nowhere = centre_of(0);
  nowhere.modulus_pa = 1;
  int32_t ties = -1;
  EXPECT_EQ(eval::bayes_material_class(nowhere, &ties), -1);
  EXPECT_EQ(ties, 0);
}

TEST(Oracle, KnnVotesTheNearestNeighbours) {
  // Two clusters on the first feature; the second feature is constant (left unscaled).
  const std::vector<double> train = {0, 5, 0.1, 5, 0.2, 5, 10, 5, 10.1, 5, 10.2, 5};
  const std::vector<int32_t> labels = {0, 0, 0, 1, 1, 1};
  const std::vector<double> query = {0.05, 5, 9.9, 5, 4.0, 5};
  const auto pred = eval::knn_predict(train, labels, query, 2, 2, 3);
  EXPECT_EQ(pred, (std::vector<int32_t>{0, 1, 0}));
}

TEST(Oracle, TouchOraclesFromRecordedVariables) {
  eval::TouchEmbeddings t;
  t.dim = 1;
  // Two classes, glass (hard, smooth) and grass (soft, rough), 20 train + 10 test samples each.
  // Both textures are below the frame's visibility here (glass: nanometres; grass: flattened
  // to texture_kappa 0.2), so the one-frame estimate must separate them by the contact: the
  // soft grass spreads over a larger, shallower imprint at the same force.
  for (int i = 0; i < 60; ++i) {
    const int32_t id = i % 2 == 0 ? 2 : 13;
    sim::MaterialSample m = centre_of(id);
    sim::ContactState c;
    c.force_n = 2 + 0.01 * i;
    c.contact_area_mm2 = id == 2 ? 30 : 80;
    c.max_gel_indentation_mm = id == 2 ? 0.3 : 0.1;
    c.kappa = id == 2 ? 1.0 : 0.3;
    c.texture_kappa = id == 2 ? 1.0 : 0.2;
    t.values.push_back(0);
    t.material.push_back(id);
    t.hard.push_back(m.hard ? 1 : 0);
    t.rough.push_back(m.rough);
    t.group.push_back("s" + std::to_string(i));
    t.is_test.push_back(i >= 40 ? 1 : 0);
    t.keys.push_back("k" + std::to_string(i));
    t.hidden_material.push_back(m);
    t.hidden_contact.push_back(c);
  }
  const auto oracles = eval::touch_oracles(t);
  ASSERT_EQ(oracles.size(), 3u);
  for (const eval::TouchOracle& o : oracles) {
    SCOPED_TRACE(eval::task_name(o.task));
    ASSERT_TRUE(o.available) << o.note;
    EXPECT_EQ(o.n, 20);
    EXPECT_DOUBLE_EQ(o.hidden_accuracy, 1.0);
    EXPECT_DOUBLE_EQ(o.frame_accuracy, 1.0);
  }
  // Without recorded variables: unavailable, with a note.
  t.hidden_material.clear();
  t.hidden_contact.clear();
  for (const eval::TouchOracle& o : eval::touch_oracles(t)) {
    EXPECT_FALSE(o.available);
    EXPECT_FALSE(o.note.empty());
  }
}

TEST(Oracle, KnnClassWeightsNeverVoteWithTheQuerysOwnObject) {
  // Rows 0-2: object "a", class 1, right at the query; rows 3-5: object "b", class 4, farther.
  const std::vector<double> rows = {0, 0, 0.01, 0, 0.02, 0, 5, 0, 5.1, 0, 5.2, 0};
  const std::vector<int32_t> classes = {1, 1, 1, 4, 4, 4};
  const std::vector<std::string> groups = {"a", "a", "a", "b", "b", "b"};
  const std::vector<size_t> queries = {0, 3};
  const auto w = eval::knn_class_weights_other_groups(rows, classes, groups, queries, 2, 2);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w[0][4], 1.0);  // row 0's own object is nearer but never counts
  EXPECT_DOUBLE_EQ(w[0][1], 0.0);
  EXPECT_DOUBLE_EQ(w[1][1], 1.0);
}

// Two graspable-looking classes whose friction ranges do not overlap, and a grip on which the
// class decides the grasp: the frames estimate equals the class row when the frames tell the
// classes apart and falls below it when they cannot.
TEST(Oracle, GraspFramesEstimateReadsMuThroughTheMaterialVote) {
  const auto cls = sim::material_classes();
  int32_t slippery = -1, grippy = -1;
  for (const sim::MaterialClass& c : cls) {
    if (slippery < 0 || c.friction.hi < cls[static_cast<size_t>(slippery)].friction.hi)
      slippery = c.id;
    if (grippy < 0 || c.friction.lo > cls[static_cast<size_t>(grippy)].friction.lo) grippy = c.id;
  }
  ASSERT_LT(cls[static_cast<size_t>(slippery)].friction.hi,
            cls[static_cast<size_t>(grippy)].friction.lo);
  sim::GraspVariables v;
  v.contact_area_mm2[0] = v.contact_area_mm2[1] = 120;
  v.finger_in_contact[0] = v.finger_in_contact[1] = true;
  // The grip force at which the grippy class holds and the slippery one does not.
  auto p_of = [&](int32_t c, double force) {
    v.grip_force_n = force;
    std::array<double, sim::kMaterialClassCount> one{};
    one[static_cast<size_t>(c)] = 1;
    const std::vector<sim::GraspVariables> vs = {v};
    const std::vector<std::array<double, sim::kMaterialClassCount>> ws = {one};
    return sim::grasp_success_given_class_weights(vs, ws, 1).value()[0];
  };
  double force = 0;
  for (double f = 5; f <= 35 && force == 0; f += 1)
    if (p_of(grippy, f) > 0.6 && p_of(slippery, f) < 0.4) force = f;
  ASSERT_GT(force, 0) << "no grip force separates the two classes";
  v.grip_force_n = force;

  for (const bool frames_differ : {true, false}) {
    SCOPED_TRACE(frames_differ ? "frames tell the classes apart" : "frames look alike");
    eval::GraspEmbeddings g;
    g.dim = 1;
    for (int i = 0; i < 80; ++i) {
      const bool is_grippy = i % 2 == 0;
      sim::MaterialSample m = centre_of(is_grippy ? grippy : slippery);
      sim::ContactState c;
      c.force_n = force / 2 + 0.001 * i;
      c.contact_area_mm2 = frames_differ && is_grippy ? 150 : 120;
      c.max_gel_indentation_mm = 0.2;
      c.kappa = c.texture_kappa = 0;  // no texture shows: only the contact can tell
      g.values.resize(g.values.size() + eval::kGraspFrames, 0.f);
      g.label.push_back(is_grippy ? 1 : 0);
      g.group.push_back("o" + std::to_string(i));
      g.is_test.push_back(i >= 40 ? 1 : 0);
      g.keys.push_back("k" + std::to_string(i));
      g.hidden_variables.push_back(v);
      g.hidden_material.push_back(m);
      g.hidden_during.push_back({c, c});
    }
    auto o = eval::grasp_frames_oracle(g);
    ASSERT_TRUE(o.ok()) << o.error().message();
    ASSERT_TRUE(o->available) << o->note;
    EXPECT_EQ(o->n, 40);
    EXPECT_DOUBLE_EQ(o->class_accuracy, 1.0);
    EXPECT_DOUBLE_EQ(o->majority_rate, 0.5);
    if (frames_differ) {
      EXPECT_DOUBLE_EQ(o->frames_accuracy, 1.0);
    } else {
      EXPECT_LE(o->frames_accuracy, 0.75);  // a vote over look-alikes is near a coin flip
    }
  }
  // Without recorded variables (real data): unavailable, with a note.
  eval::GraspEmbeddings none;
  none.is_test = {1};
  none.label = {1};
  none.group = {"x"};
  auto o = eval::grasp_frames_oracle(none);
  ASSERT_TRUE(o.ok());
  EXPECT_FALSE(o->available);
  EXPECT_FALSE(o->note.empty());
}

// The seeded reference encoder plus one zero-shot head per task (it has none of its own).
std::vector<std::byte> reference_model() {
  quantize::ReferenceEncoderOptions o;
  o.dtype = quantize::EncoderDType::kFloat32;
  o.resolution = 96;
  o.seed = 5;
  o.embedding_dim = 32;
  o.calibration_frames = 2;
  o.preprocess = quantize::deployment_preprocessor();
  auto enc = quantize::build_reference_encoder(o);
  EXPECT_TRUE(enc.ok()) << enc.error().message();
  if (!enc.ok()) return {};
  auto model = testing::load_model(enc->file);
  if (model == nullptr) return {};
  quantize::MetadataSpec meta = quantize::metadata_spec_from(model->metadata());
  for (Task t : eval::kAllTasks) {
    quantize::ZeroShotHeadSpec z;
    z.name = t == Task::kHard ? "hard" : t == Task::kRough ? "rough" : eval::task_name(t);
    for (std::string_view c : eval::task_classes(t)) z.class_names.emplace_back(c);
    z.prompt_template = "{}";
    z.prompt_matrix.assign(z.class_names.size() * 32, 0.1f);
    meta.zero_shot_heads.push_back(std::move(z));
  }
  auto b = quantize::rebuild_with_metadata(*model, meta);
  EXPECT_TRUE(b.ok()) << b.error().message();
  return b.ok() ? b->finish() : std::vector<std::byte>{};
}

eval::TaskResult cell(Task task, Method method, double accuracy, double majority, int64_t n) {
  eval::TaskResult r;
  r.task = task;
  r.method = method;
  r.available = true;
  r.accuracy = accuracy;
  r.majority = majority;
  r.n = n;
  return r;
}

TEST(Trust, ReportFiguresAreRecordedAndChanceZeroShotHeadsDropped) {
  auto model = testing::load_model(reference_model());
  ASSERT_NE(model, nullptr);
  ASSERT_FALSE(model->metadata().zero_shot_heads.empty());
  eval::EvalReport report;
  report.touch_dir = "t100k";
  report.touch_format = "touch100k";
  report.touch_split = eval::SplitInfo{"recorded", 80, 20, 10, 5};
  report.grasp_dir = "feel";
  report.grasp_format = "feel_repacked";
  report.grasp_split = eval::SplitInfo{"recorded", 40, 10, 8, 2};
  for (Task t : eval::kAllTasks) {
    report.results.push_back(cell(t, Method::kModelHeads, 0.9, 0.6, 200));
    // Zero-shot: only the hard/soft head beats its majority.
    report.results.push_back(cell(t, Method::kZeroShot, t == Task::kHard ? 0.9 : 0.55, 0.6, 200));
  }
  std::vector<std::string> lines;
  auto bytes = eval::model_with_trust(*model, report, {}, &lines);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto copy = testing::load_model(*bytes);
  ASSERT_NE(copy, nullptr);
  const Metadata& m = copy->metadata();
  for (const LinearHead& h : m.linear_heads) {
    SCOPED_TRACE(std::string(h.name));
    ASSERT_TRUE(h.trust.present);
    EXPECT_FLOAT_EQ(h.trust.accuracy, 0.9f);
    EXPECT_FLOAT_EQ(h.trust.majority, 0.6f);
    EXPECT_EQ(h.trust.n, 200);
    EXPECT_NE(h.trust.test_set.find("t100k"), std::string_view::npos);
    EXPECT_TRUE(head_trusted(h.trust));
  }
  ASSERT_TRUE(m.grasp_head.present);
  EXPECT_NE(m.grasp_head.trust.test_set.find("feel"), std::string_view::npos);
  ASSERT_EQ(m.zero_shot_heads.size(), 1u) << "only the zero-shot head that beats chance stays";
  EXPECT_EQ(eval::task_of_head(m.zero_shot_heads[0].name).value(), Task::kHard);
  EXPECT_EQ(lines.size(), m.linear_heads.size() + 1 + model->metadata().zero_shot_heads.size());
  // Kept on request.
  eval::TrustRecordOptions keep;
  keep.drop_untrusted_zero_shot = false;
  auto all = eval::model_with_trust(*model, report, keep);
  ASSERT_TRUE(all.ok());
  auto kept = testing::load_model(*all);
  ASSERT_NE(kept, nullptr);
  EXPECT_EQ(kept->metadata().zero_shot_heads.size(), model->metadata().zero_shot_heads.size());
}

}  // namespace
}  // namespace tlvlink
