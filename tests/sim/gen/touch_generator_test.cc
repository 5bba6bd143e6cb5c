// The touch-session generator: sizes, session structure, determinism, order independence,
// consistent descriptions, errors, and its generation rate.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <regex>
#include <set>
#include <string>

#include "gen/session_names.h"
#include "support/random.h"
#include "tlvlink/sim/describe.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {
namespace {

TouchSetOptions small_touch_options(uint64_t seed) {
  TouchSetOptions o;
  o.sessions = 3;
  o.frames_per_session = 2;
  o.vision_height = 48;
  o.vision_width = 64;
  o.seed = seed;
  return o;
}

std::unique_ptr<TouchSampleGenerator> make(const TouchSetOptions& o) {
  auto g = TouchSampleGenerator::create(o);
  EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message());
  return g.ok() ? std::move(g).value() : nullptr;
}

bool finite(const ContactState& s) {
  for (double v : {s.force_n, s.press_mm, s.max_gel_indentation_mm, s.kappa, s.contact_area_mm2,
                   s.contact_radius_mm, s.stick_radius_mm, s.slip_ratio, s.mean_shear_mm}) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

bool same(const TouchSample& a, const TouchSample& b) {
  return a.session == b.session && a.frame_index == b.frame_index && a.object_id == b.object_id &&
         a.touch.rgb == b.touch.rgb && a.vision.rgb == b.vision.rgb &&
         a.sentence_desc == b.sentence_desc && a.phrases == b.phrases &&
         a.material.modulus_pa == b.material.modulus_pa && a.contact.force_n == b.contact.force_n;
}

TEST(TouchGenerator, SessionsFramesAndContent) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  auto gen = make(small_touch_options(seed));
  ASSERT_NE(gen, nullptr);
  ASSERT_EQ(gen->size(), 6);
  auto describer = Describer::create().value();
  const std::regex session_format("[0-9]{8}_[0-9]{6}");
  std::vector<TouchSample> s(6);
  std::set<std::string> sessions;
  for (int64_t i = 0; i < gen->size(); ++i) {
    ASSERT_TRUE(gen->generate(i, s[static_cast<size_t>(i)]).ok());
    const TouchSample& t = s[static_cast<size_t>(i)];
    EXPECT_TRUE(std::regex_match(t.session, session_format)) << t.session;
    EXPECT_EQ(t.frame_index, i % 2);
    EXPECT_EQ(t.object_id, i / 2);
    EXPECT_EQ(t.touch.height, 240);
    EXPECT_EQ(t.touch.width, 320);
    EXPECT_EQ(t.touch.rgb.size(), 240u * 320u * 3u);
    EXPECT_EQ(t.vision.rgb.size(), 48u * 64u * 3u);
    EXPECT_TRUE(finite(t.contact));
    EXPECT_TRUE(t.contact.in_contact) << "every press touches the gel";
    EXPECT_GE(t.contact.force_n, 0.4);
    EXPECT_LE(t.contact.force_n, 16);
    EXPECT_FALSE(t.sentence_desc.empty());
    EXPECT_GE(t.phrases.size(), 1u);
    for (const std::string& p : t.phrases) {
      ASSERT_NE(describer->find(p), nullptr) << p;
    }
    EXPECT_EQ(t.material.hard, t.material.modulus_pa > kHardModulusPa);
    sessions.insert(t.session);
  }
  EXPECT_EQ(sessions.size(), 3u) << "one name per session, unique";
  for (size_t i = 0; i < 6; i += 2) {  // frames of a session: one object, different presses
    EXPECT_EQ(s[i].session, s[i + 1].session);
    EXPECT_EQ(s[i].material.modulus_pa, s[i + 1].material.modulus_pa);
    EXPECT_NE(s[i].touch.rgb, s[i + 1].touch.rgb);
  }
}

TEST(TouchGenerator, DeterministicAndIndependentOfOrder) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  auto a = make(small_touch_options(seed)), b = make(small_touch_options(seed));
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  std::vector<TouchSample> forward(6), backward(6);
  for (int64_t i = 0; i < 6; ++i) ASSERT_TRUE(a->generate(i, forward[static_cast<size_t>(i)]).ok());
  for (int64_t i = 5; i >= 0; --i)
    ASSERT_TRUE(b->generate(i, backward[static_cast<size_t>(i)]).ok());
  for (size_t i = 0; i < 6; ++i) EXPECT_TRUE(same(forward[i], backward[i])) << "sample " << i;
  TouchSample again;  // reusing a filled sample's buffers changes nothing
  again = forward[5];
  ASSERT_TRUE(a->generate(2, again).ok());
  EXPECT_TRUE(same(again, forward[2]));
  auto other = make(small_touch_options(seed + 1));
  TouchSample o;
  ASSERT_TRUE(other->generate(0, o).ok());
  EXPECT_FALSE(same(o, forward[0]));
}

TEST(TouchGenerator, SessionNamesAreUniqueAndOrdered) {
  std::set<std::string> names;
  std::string last;
  for (int64_t s = 0; s < 20000; ++s) {
    const std::string n = internal::session_name(7, s);
    EXPECT_GT(n, last);  // fixed width: later sessions sort later
    last = n;
    names.insert(n);
  }
  EXPECT_EQ(names.size(), 20000u);
  EXPECT_EQ(internal::session_name(7, 5), internal::session_name(7, 5));
  EXPECT_EQ(internal::object_name(9, 42), "natural_fabric_0042");
}

TEST(TouchGenerator, BadOptionsAndIndicesAreErrors) {
  TouchSetOptions o = small_touch_options(1);
  o.sessions = 0;
  EXPECT_EQ(TouchSampleGenerator::create(o).error().code(), ErrorCode::kInvalidArgument);
  o = small_touch_options(1);
  o.vision_width = 0;
  EXPECT_EQ(TouchSampleGenerator::create(o).error().code(), ErrorCode::kInvalidArgument);
  o = small_touch_options(1);
  o.sensor = "no-such-sensor";
  EXPECT_FALSE(TouchSampleGenerator::create(o).ok());
  auto gen = make(small_touch_options(1));
  TouchSample s;
  EXPECT_EQ(gen->generate(-1, s).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(gen->generate(gen->size(), s).error().code(), ErrorCode::kInvalidArgument);
}

TEST(TouchGenerator, MixedProfileSetsDrawAProfilePerSession) {
  // "gelsight-mini,digit": each session on one profile; a session's Mini frames are the bytes
  // a Mini-only set of the same seed gives (same material, press, sensor and noise seeds).
  TouchSetOptions mixed = small_touch_options(5);
  mixed.sessions = 12;
  mixed.sensor = "gelsight-mini,digit";
  TouchSetOptions mini = mixed;
  mini.sensor = "gelsight-mini";
  auto g = make(mixed), m = make(mini);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(m, nullptr);
  std::set<std::string> seen;
  TouchSample s, t;
  for (int64_t i = 0; i < g->size(); ++i) {
    ASSERT_TRUE(g->generate(i, s).ok());
    seen.insert(s.sensor);
    if (s.frame_index == 1) {  // both frames of a session on one profile
      TouchSample first;
      ASSERT_TRUE(g->generate(i - 1, first).ok());
      EXPECT_EQ(first.sensor, s.sensor);
    }
    if (s.sensor == "gelsight-mini") {
      EXPECT_EQ(s.touch.height, 240);
      ASSERT_TRUE(m->generate(i, t).ok());
      EXPECT_EQ(s.touch.rgb, t.touch.rgb) << "sample " << i;
      EXPECT_EQ(t.sensor, "gelsight-mini");
    } else {
      EXPECT_EQ(s.sensor, "digit");
      EXPECT_EQ(s.touch.height, 320);  // DIGIT frames are portrait (tools/sim/REFERENCE.md)
      EXPECT_EQ(s.touch.width, 240);
    }
  }
  EXPECT_EQ(seen.size(), 2u) << "12 sessions should draw both profiles";
  mixed.sensor = "gelsight-mini,nosuch";
  EXPECT_FALSE(TouchSampleGenerator::create(mixed).ok());
}

TEST(TouchGenerator, MarkersFractionDrawsMarkedGelsPerSession) {
  // Half the sessions on gels with markers: their frames differ from the unmarked set's, the
  // others are the same bytes; both frames of a session agree.
  TouchSetOptions half = small_touch_options(9);
  half.sessions = 16;
  half.markers_fraction = 0.5;
  TouchSetOptions none = half;
  none.markers_fraction = 0;
  auto g = make(half), n = make(none);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(n, nullptr);
  int marked = 0;
  TouchSample a, b;
  for (int64_t session = 0; session < half.sessions; ++session) {
    bool differs[2];
    for (int32_t f = 0; f < 2; ++f) {
      ASSERT_TRUE(g->generate(session * 2 + f, a).ok());
      ASSERT_TRUE(n->generate(session * 2 + f, b).ok());
      differs[f] = a.touch.rgb != b.touch.rgb;
    }
    EXPECT_EQ(differs[0], differs[1]) << "session " << session;
    marked += differs[0] ? 1 : 0;
  }
  EXPECT_GT(marked, 2);
  EXPECT_LT(marked, 14);
  half.markers_fraction = 1.5;
  EXPECT_EQ(TouchSampleGenerator::create(half).error().code(), ErrorCode::kInvalidArgument);
}

TEST(TouchGenerator, Rate) {
  TouchSetOptions o = small_touch_options(3);
  o.sessions = 10;
  o.frames_per_session = 3;
  o.vision_height = 240;
  o.vision_width = 320;
  auto gen = make(o);
  ASSERT_NE(gen, nullptr);
  TouchSample s;
  ASSERT_TRUE(gen->generate(0, s).ok());  // first frame sizes the buffers
  const auto t0 = std::chrono::steady_clock::now();
  for (int64_t i = 1; i < gen->size(); ++i) ASSERT_TRUE(gen->generate(i, s).ok());
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "touch generator: %.1f samples/s (240x320 touch + 240x320 vision + descriptions, 1 thread)\n",
      static_cast<double>(gen->size() - 1) / sec);
}

}  // namespace
}  // namespace tlvlink::sim
