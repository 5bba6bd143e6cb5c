// The shipped int8 model reads touch, not the codec (issue 29): the same simulated scenes of
// unseen sensor instances, as rendered and through every image path (JPEG q95 / q90 / q75, the
// sensor's live decode), and the real frames beside the repository (re-encoded, shifted 3 DN)
// when they are there. Each bound below is what the shipped files were measured to reach
// (firmware/models/README.md "Stability", 200 scenes); the scenes here are another seed's, so
// the bounds carry a margin, stated per line. A model that reads the codec again fails here.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tlvlink/eval/stability.h"
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
};

// The live decode meets issue 29's targets (0.97 / 95 %) on the 200 measured scenes; the other
// paths are held to what the shipped files reach, 0.02 below (another seed's scenes).
constexpr Bound kBounds[] = {
    {"simulated", "live gelsight-mini", 0.96, 0.85},
    {"simulated", "live digit", 0.96, 0.85},
    {"simulated", "jpeg-q95", 0.93, 0.75},
    {"simulated", "jpeg-q90", 0.93, 0.75},
    {"simulated", "jpeg-q75", 0.80, 0.65},
    {"real", "jpeg-q90", 0.90, 0.80},
    {"real", "+3 DN", 0.99, 0.90},
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
      if (h.trusted) EXPECT_GE(h.rate(), b.min_agreement) << b.source << " " << b.path << " " << h.head;
    }
  }
}

}  // namespace
}  // namespace tlvlink::eval
