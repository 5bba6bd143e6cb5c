// The shipped int8 model reads touch, not the codec (issue 29): the same simulated scenes of
// unseen sensor instances, as rendered and through every image path (JPEG q95 / q90 / q75, the
// sensor's live decode), and the real frames beside the repository (re-encoded, shifted 3 DN)
// when they are there (skipped with a message where ../shared is absent). A model that reads the
// codec again fails here.

#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tlvlink/eval/stability.h"
#include "tlvlink/eval/tasks.h"
#include "tlvlink/model.h"

namespace tlvlink::eval {
namespace {

constexpr const char* kShipped = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";
constexpr const char* kRealFrames = TLVLINK_SOURCE_DIR "/../shared/real-frames";

struct Bound {
  const char* source;
  const char* path;
  double min_cosine;     // the smallest cosine of any item
  double min_agreement;  // every trusted head's share of unchanged answers
  double min_two_class;  // the same for the two-class heads (hard/soft, rough/smooth)
};

// What the shipped files reach on these 48 scenes (seed 31) and the 130 real frames, less a
// margin: the figures are deterministic for a given model, so the margin only absorbs a re-made
// model's ordinary spread (0.01-0.03 of cosine, one or two answers in 48) while a model that
// reads the codec again (the files before issue 29: cosine -0.3 on JPEG q95, 0.18 through the
// Mini's live decode) fails by far. The live decode and real frames at q95/q90 hold issue 29's
// cosine target (0.97). The two-class heads, fitted with the view penalty, hold the 95 %
// agreement target on the README's 200 scenes and keep 95.2-100 % here (the heads before the
// penalty: rough/smooth 83.3 % on JPEG q75, 92.6 % on the live Mini); the material head is held
// to the level reached, below the target (firmware/models/README.md "Stability" says why).
constexpr Bound kBounds[] = {
    // measured: cosine, material, the two-class heads' lower
    {"simulated", "live gelsight-mini", 0.97, 0.80, 0.90},  // 0.995, 88.9 %, 96.3 %
    {"simulated", "live digit", 0.97, 0.85, 0.90},          // 0.999, 95.2 %, 95.2 %
    {"simulated", "jpeg-q95", 0.95, 0.75, 0.90},            // 0.982, 83.3 %, 95.8 %
    {"simulated", "jpeg-q90", 0.95, 0.65, 0.90},            // 0.986, 75.0 %, 95.8 %
    {"simulated", "jpeg-q75", 0.92, 0.55, 0.90},            // 0.966, 64.6 %, 95.8 %
    {"real", "jpeg-q90", 0.95, 0.85, 0.95},                 // 0.970, 96.9 %, 99.2 %
    {"real", "+3 DN", 0.99, 0.95, 0.97},                    // 0.999, 98.5 %, 100 %
};

TEST(ShippedStability, TheSameTouchEmbedsAlikeThroughEveryPath) {
  auto model = Model::load_file(kShipped);
  ASSERT_TRUE(model.ok()) << model.error().message();
  StabilityOptions o;
  o.scenes = 48;  // ~4 s: enough scenes to meet the worst ones, few enough for every CI run
  o.seed = 31;    // not the README table's seed (29)
  o.real_frames_dir = kRealFrames;
  if (!std::filesystem::is_directory(kRealFrames)) o.real_frames_dir.clear();
  auto r = measure_stability(**model, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  std::printf("%s", format_stability(*r).c_str());
  for (const Bound& b : kBounds) {
    const PathStability* p = nullptr;
    for (const PathStability& x : r->paths)
      if (x.source == b.source && x.path == b.path) p = &x;
    if (p == nullptr && std::string(b.source) == "real") {
      std::printf("real frames not measured (%s): the real-frame bounds are not checked\n",
                  r->real_note.c_str());
      continue;
    }
    ASSERT_NE(p, nullptr) << b.source << " " << b.path;
    EXPECT_GE(p->cos_min, b.min_cosine) << b.source << " " << b.path << ", worst: " << p->worst;
    for (const HeadAgreement& h : p->heads) {
      if (!h.trusted) continue;
      EXPECT_GE(h.rate(), b.min_agreement) << b.source << " " << b.path << " " << h.head;
      auto task = task_of_head(h.head);
      if (task.ok() && task_class_count(*task) == 2) {
        EXPECT_GE(h.rate(), b.min_two_class) << b.source << " " << b.path << " " << h.head;
      }
    }
  }
}

}  // namespace
}  // namespace tlvlink::eval
