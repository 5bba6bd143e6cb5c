// "Same graph, new metadata": rebuild_with_metadata round trips bit-identically (fp32 and int8,
// both executors), fitted heads written into a model are what the runtime path applies, and a
// model without an embedding output is refused with a clear error.

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/random.h"
#include "support/test_models.h"
#include "tlvlink/eval/eval.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/executor.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/heads/head_math.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

std::vector<std::byte> reference_model(quantize::EncoderDType dtype) {
  quantize::ReferenceEncoderOptions o;
  o.dtype = dtype;
  o.resolution = 96;
  o.seed = 5;
  o.embedding_dim = 32;
  o.calibration_frames = 2;
  o.preprocess = quantize::deployment_preprocessor();
  auto enc = quantize::build_reference_encoder(o);
  EXPECT_TRUE(enc.ok()) << enc.error().message();
  return enc.ok() ? enc->file : std::vector<std::byte>{};
}

std::vector<std::byte> run(const Model& m, ExecutorKind kind, const std::vector<float>& x) {
  auto e = make_executor(m, kind, {});
  EXPECT_TRUE(e.ok()) << e.error().message();
  if (!e.ok()) return {};
  std::memcpy((*e)->input(0).data(), x.data(), (*e)->input(0).size());
  const Status s = (*e)->invoke();
  EXPECT_TRUE(s.ok()) << s.error().message();
  const auto out = (*e)->output(0);
  return {out.begin(), out.end()};
}

void expect_same_outputs(const Model& a, const Model& b) {
  for (uint64_t seed : {1u, 2u}) {
    auto x = quantize::synthetic_input(a, seed);
    ASSERT_TRUE(x.ok()) << x.error().message();
    for (ExecutorKind kind : {ExecutorKind::kReference, ExecutorKind::kXnnpack}) {
      EXPECT_EQ(run(a, kind, *x), run(b, kind, *x))
          << executor_kind_name(kind) << " output differs, frame seed " << seed;
    }
  }
}

TEST(ModelCopy, RebuildRoundTripIsBitIdentical) {
  for (auto dtype : {quantize::EncoderDType::kFloat32, quantize::EncoderDType::kInt8}) {
    auto original = testing::load_model(reference_model(dtype));
    ASSERT_NE(original, nullptr);
    auto b = quantize::rebuild_with_metadata(*original,
                                             quantize::metadata_spec_from(original->metadata()));
    ASSERT_TRUE(b.ok()) << b.error().message();
    auto copy = testing::load_model(b->finish());
    ASSERT_NE(copy, nullptr);
    const Graph &g0 = original->graph(), &g1 = copy->graph();
    ASSERT_EQ(g0.tensors.size(), g1.tensors.size());
    ASSERT_EQ(g0.operators.size(), g1.operators.size());
    for (size_t i = 0; i < g0.tensors.size(); ++i) {
      EXPECT_EQ(g0.tensors[i].name, g1.tensors[i].name);
      EXPECT_TRUE(g0.tensors[i].shape == g1.tensors[i].shape);
      ASSERT_EQ(g0.tensors[i].data.size(), g1.tensors[i].data.size());
      // std::equal, not memcmp: an activation tensor has no data (a null span).
      EXPECT_TRUE(std::equal(g0.tensors[i].data.begin(), g0.tensors[i].data.end(),
                             g1.tensors[i].data.begin(), g1.tensors[i].data.end()));
      EXPECT_TRUE(std::equal(g0.tensors[i].quant.scale.begin(), g0.tensors[i].quant.scale.end(),
                             g1.tensors[i].quant.scale.begin(), g1.tensors[i].quant.scale.end()));
    }
    const Metadata &m0 = original->metadata(), &m1 = copy->metadata();
    EXPECT_EQ(m0.name, m1.name);
    EXPECT_EQ(m0.provenance.content_checksum, m1.provenance.content_checksum);
    ASSERT_EQ(m0.golden.size(), m1.golden.size());
    for (size_t i = 0; i < m0.golden.size(); ++i) {
      EXPECT_TRUE(std::equal(m0.golden[i].output.begin(), m0.golden[i].output.end(),
                             m1.golden[i].output.begin(), m1.golden[i].output.end()));
    }
    expect_same_outputs(*original, *copy);
  }
}

// Embeddings with a linear structure the probes can find: label c shifts dimension c.
eval::EmbeddingSet synthetic_set(int32_t dim, uint64_t seed) {
  testing::Rng rng(seed);
  eval::EmbeddingSet set;
  eval::TouchEmbeddings t;
  t.dim = dim;
  for (int i = 0; i < 200; ++i) {
    const int32_t material = i % 20, hard = (i / 20) % 2, rough = i % 3 == 0 ? -1 : (i / 7) % 2;
    for (int32_t j = 0; j < dim; ++j) {
      float v = rng.normal(0, 1);
      if (j == material) v += 4;
      if (j == 20 && hard == 1) v += 4;
      if (j == 21 && rough == 1) v += 4;
      t.values.push_back(v);
    }
    t.material.push_back(material);
    t.hard.push_back(hard);
    t.rough.push_back(rough);
    t.group.push_back("s" + std::to_string(i / 4));
    t.is_test.push_back(i >= 160 ? 1 : 0);
    t.keys.push_back(std::to_string(i));
  }
  set.touch = std::move(t);
  eval::GraspEmbeddings g;
  g.dim = dim;
  for (int i = 0; i < 100; ++i) {
    const int32_t label = i % 2;
    for (int32_t f = 0; f < eval::kGraspFrames; ++f) {
      for (int32_t j = 0; j < dim; ++j) {
        // Finger A and B during the lift (frames 1 and 4) shift every dimension when held.
        const bool during = f == 1 || f == 4;
        g.values.push_back(rng.normal(0, 1) + (during && label == 1 ? 1.5f : 0.0f));
      }
    }
    // Each finger's difference features: the first one larger when held.
    for (int32_t f = 0; f < heads::kFingers * heads::kDifferenceFeatures; ++f) {
      const bool first = f % heads::kDifferenceFeatures == 0;
      g.difference.push_back(rng.normal(0, 1) + (first && label == 1 ? 1.0f : 0.0f));
    }
    g.label.push_back(label);
    g.group.push_back("o" + std::to_string(i / 2));
    g.is_test.push_back(i >= 80 ? 1 : 0);
    g.keys.push_back(std::to_string(i));
  }
  set.grasp = std::move(g);
  return set;
}

TEST(ModelHeads, WrittenHeadsAreAppliedByTheRuntimePathIdentically) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  auto original = testing::load_model(reference_model(quantize::EncoderDType::kFloat32));
  ASSERT_NE(original, nullptr);
  const int32_t dim = original->metadata().embedding_dim;
  const eval::EmbeddingSet set = synthetic_set(dim, seed);
  auto heads = eval::fit_heads(set, {});
  ASSERT_TRUE(heads.ok()) << heads.error().message();
  ASSERT_EQ(heads->linear.size(), 3u);
  ASSERT_TRUE(heads->grasp.has_value());
  auto bytes = eval::model_with_heads(*original, *heads, {});
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto model = testing::load_model(*bytes);
  ASSERT_NE(model, nullptr);
  const Metadata& m = model->metadata();
  // The reference encoder's random heads are replaced by name; zero-shot heads were added.
  ASSERT_EQ(m.linear_heads.size(), 3u);
  EXPECT_EQ(m.zero_shot_heads.size(), 4u);
  EXPECT_TRUE(m.grasp_head.present);
  EXPECT_EQ(m.grasp_head.feature_layout,
            "A.before,A.during,A.difference,B.before,B.during,B.difference");
  EXPECT_EQ(m.grasp_head.weight.size(),
            4u * static_cast<size_t>(dim) + 2u * heads::kDifferenceFeatures);
  EXPECT_NE(m.provenance.training.find("heads_fit"), std::string_view::npos);
  expect_same_outputs(*original, *model);

  // The runtime's head path (`tlvlink infer`, the daemon) gives exactly the fitted heads' logits.
  const eval::TouchEmbeddings& t = *set.touch;
  auto evaluator = heads::HeadEvaluator::create(m);
  ASSERT_TRUE(evaluator.ok()) << evaluator.error().message();
  for (size_t i = 0; i < t.size(); i += 17) {
    ASSERT_TRUE(evaluator->evaluate(t.row(i)).ok());
    const std::span<const heads::HeadResult> p = evaluator->results();
    ASSERT_EQ(p.size(), 3u + 4u);
    for (size_t h = 0; h < 3; ++h) {
      std::vector<float> logits(heads->linear[h].bias.size());
      heads::linear_logits(heads->linear[h].weight, heads->linear[h].bias, t.row(i), logits);
      EXPECT_EQ(p[h].name, heads->linear[h].name);
      EXPECT_TRUE(std::equal(logits.begin(), logits.end(), p[h].logits.begin(), p[h].logits.end()))
          << "head " << p[h].name << " row " << i;
    }
  }
  // The grasp head with its difference features: the runtime's probability is eval's logit.
  const eval::GraspEmbeddings& g = *set.grasp;
  for (size_t i = 0; i < g.size(); i += 7) {
    std::vector<std::span<const float>> features;
    for (const heads::GraspFeature& f : evaluator->grasp_layout())
      features.push_back(g.feature(i, f));
    auto p = evaluator->grasp_probability(features);
    ASSERT_TRUE(p.ok()) << p.error().message();
    auto logit = eval::grasp_head_logit(m.grasp_head.weight, m.grasp_head.bias,
                                        m.grasp_head.feature_layout, g, i);
    ASSERT_TRUE(logit.ok()) << logit.error().message();
    EXPECT_EQ(*p, heads::sigmoid(*logit)) << "episode " << i;
  }
  // Scoring the stored heads reproduces the fitted probes' test results exactly.
  eval::EvalOptions o;
  o.oracle_samples = 0;
  auto r = eval::evaluate_embeddings(m, set, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  for (eval::Task task : eval::kAllTasks) {
    const eval::TaskResult* probe = r->find(task, eval::Method::kProbe);
    const eval::TaskResult* stored = r->find(task, eval::Method::kModelHeads);
    ASSERT_TRUE(probe->available && stored->available) << eval::task_name(task);
    EXPECT_EQ(probe->correct, stored->correct) << eval::task_name(task);
    EXPECT_EQ(probe->n, stored->n);
    // The structure is linear and strong: far above chance on held-out rows.
    EXPECT_GT(probe->accuracy, probe->chance + 0.3) << eval::task_name(task);
  }
  EXPECT_EQ(r->find(eval::Task::kRough, eval::Method::kProbe)->unlabelled,
            13);  // i % 3 == 0 in 160..199
}

// Grasp episodes of two sensor models whose grasp signal points opposite ways: one head for
// both cannot separate them, a head per model can (as the simulator's Mini and DIGIT optics
// differ, firmware/models/README.md).
eval::EmbeddingSet two_sensor_grasp_set(int32_t dim, uint64_t seed) {
  testing::Rng rng(seed);
  eval::EmbeddingSet set;
  eval::GraspEmbeddings g;
  g.dim = dim;
  for (int i = 0; i < 240; ++i) {
    const int32_t label = i % 2;
    const bool digit = (i / 2) % 2 == 1;
    for (int32_t f = 0; f < eval::kGraspFrames; ++f) {
      const bool during = f == 1 || f == 4;
      const float shift = during && label == 1 ? (digit ? -1.5f : 1.5f) : 0.0f;
      for (int32_t j = 0; j < dim; ++j) g.values.push_back(rng.normal(0, 1) + shift);
    }
    for (int32_t f = 0; f < heads::kFingers * heads::kDifferenceFeatures; ++f)
      g.difference.push_back(rng.normal(0, 1));
    g.label.push_back(label);
    g.sensor.push_back(digit ? "digit" : "gelsight-mini");
    g.group.push_back("o" + std::to_string(i / 4));
    g.is_test.push_back(i >= 160 ? 1 : 0);
    g.keys.push_back(std::to_string(i));
  }
  set.grasp = std::move(g);
  return set;
}

TEST(ModelHeads, AGraspHeadPerSensorModelIsFittedOnItsEpisodesAndUsedForThem) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  auto original = testing::load_model(reference_model(quantize::EncoderDType::kFloat32));
  ASSERT_NE(original, nullptr);
  const int32_t dim = original->metadata().embedding_dim;
  const eval::EmbeddingSet set = two_sensor_grasp_set(dim, seed);
  eval::HeadFitOptions one;
  one.grasp_per_sensor = false;
  auto single = eval::fit_heads(set, one);
  ASSERT_TRUE(single.ok()) << single.error().message();
  EXPECT_TRUE(single->sensor_grasp.empty());
  auto fitted = eval::fit_heads(set, {});
  ASSERT_TRUE(fitted.ok()) << fitted.error().message();
  ASSERT_EQ(fitted->sensor_grasp.size(), 2u);
  EXPECT_EQ(fitted->sensor_grasp[0].sensors, std::vector<std::string>{"digit"});
  EXPECT_EQ(fitted->sensor_grasp[1].sensors, std::vector<std::string>{"gelsight-mini"});
  // Fitted side by side on three threads: the same heads in the same order, weight for weight.
  eval::HeadFitOptions three;
  three.threads = 3;
  auto parallel = eval::fit_heads(set, three);
  ASSERT_TRUE(parallel.ok()) << parallel.error().message();
  ASSERT_TRUE(parallel->grasp.has_value() && fitted->grasp.has_value());
  EXPECT_EQ(parallel->grasp->weight, fitted->grasp->weight);
  EXPECT_EQ(parallel->grasp->bias, fitted->grasp->bias);
  ASSERT_EQ(parallel->sensor_grasp.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(parallel->sensor_grasp[i].sensors, fitted->sensor_grasp[i].sensors);
    EXPECT_EQ(parallel->sensor_grasp[i].weight, fitted->sensor_grasp[i].weight);
  }
  auto bytes = eval::model_with_heads(*original, *fitted, {});
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto model = testing::load_model(*bytes);
  ASSERT_NE(model, nullptr);
  const Metadata& m = model->metadata();
  ASSERT_EQ(m.sensor_grasp_heads.size(), 2u);

  // eval scores each episode with its sensor's head, as the runtime picks it.
  eval::EvalOptions o;
  o.oracle_samples = 0;
  auto r = eval::evaluate_embeddings(m, set, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  const eval::TaskResult* used = r->find(eval::Task::kGrasp, eval::Method::kModelHeads);
  ASSERT_TRUE(used != nullptr && used->available);
  ASSERT_EQ(r->grasp_head_cells.size(), 3u);
  const eval::TaskResult& any = r->grasp_head_cells[0];
  EXPECT_EQ(any.n, used->n);
  EXPECT_EQ(r->grasp_head_cells[1].n + r->grasp_head_cells[2].n, used->n);
  // 80 test episodes, the signal 1.5 SD on every dimension: per sensor nearly all right, one
  // head for both near chance (the shifts cancel). 20 points is far beyond the noise of 80 items.
  EXPECT_GT(used->accuracy, any.accuracy + 0.2) << used->accuracy << " vs " << any.accuracy;
  EXPECT_GT(used->accuracy, 0.85);
  const auto evaluator = heads::HeadEvaluator::create(m);
  ASSERT_TRUE(evaluator.ok());
  const eval::GraspEmbeddings& g = *set.grasp;
  int64_t right = 0, n = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_test[i] == 0) continue;
    std::vector<std::span<const float>> features;
    for (const heads::GraspFeature& f : evaluator->grasp_layout())
      features.push_back(g.feature(i, f));
    auto p = evaluator->grasp_probability(features, evaluator->grasp_head_for(g.sensor[i]));
    ASSERT_TRUE(p.ok()) << p.error().message();
    right += (*p > 0.5f ? 1 : 0) == g.label[i];
    ++n;
  }
  EXPECT_EQ(right, used->correct) << "the runtime's choice of head is eval's";
  EXPECT_EQ(n, used->n);

  // Trust records: each head its own; a set holding one sensor's episodes only says nothing of
  // the other sensor's head, whose record stays as it was (here: none).
  eval::EmbeddingSet digit_only = set;
  for (std::string& s : digit_only.grasp->sensor) s = "digit";
  auto d = eval::evaluate_embeddings(m, digit_only, o);
  ASSERT_TRUE(d.ok()) << d.error().message();
  ASSERT_EQ(d->grasp_head_cells.size(), 3u);
  EXPECT_EQ(d->grasp_head_cells[2].n, 0) << "no gelsight-mini episode";
  auto recorded = eval::model_with_trust(*model, *d, {}, nullptr);
  ASSERT_TRUE(recorded.ok()) << recorded.error().message();
  auto with_trust = testing::load_model(*recorded);
  ASSERT_NE(with_trust, nullptr);
  const Metadata& t = with_trust->metadata();
  EXPECT_TRUE(t.grasp_head.trust.present);
  EXPECT_EQ(t.grasp_head.trust.n, used->n);
  ASSERT_EQ(t.sensor_grasp_heads.size(), 2u);
  EXPECT_TRUE(t.sensor_grasp_heads[0].trust.present);
  EXPECT_EQ(t.sensor_grasp_heads[0].trust.n, used->n) << "every episode is a DIGIT one now";
  EXPECT_FALSE(t.sensor_grasp_heads[1].trust.present) << "no Mini episode: no Mini record";
}

TEST(ModelHeads, ModelWithoutEmbeddingOutputIsRefused) {
  auto original = testing::load_model(reference_model(quantize::EncoderDType::kFloat32));
  ASSERT_NE(original, nullptr);
  quantize::MetadataSpec spec = quantize::metadata_spec_from(original->metadata());
  spec.embedding_dim = 0;
  spec.linear_heads.clear();
  spec.zero_shot_heads.clear();
  spec.has_grasp_head = false;
  auto b = quantize::rebuild_with_metadata(*original, spec);
  ASSERT_TRUE(b.ok());
  auto model = testing::load_model(b->finish());
  ASSERT_NE(model, nullptr);
  auto e = eval::Embedder::create(*model, {});
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().code(), ErrorCode::kModelUnsupported);
  EXPECT_NE(std::string(e.error().message()).find("no embedding output"), std::string::npos)
      << e.error().message();
}

}  // namespace
}  // namespace tlvlink
