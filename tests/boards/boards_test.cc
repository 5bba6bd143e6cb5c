// Boards, scenes, strip and the package's CPU check: every shipped board and scene loads; a
// scene becomes a daemon configuration the daemon accepts; strip keeps exactly the scene's
// heads and the result verifies; each kind of bad input is an error naming what was wrong.

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "support/temp_dir.h"
#include "tlvlink/boards/board.h"
#include "tlvlink/boards/build_options.h"
#include "tlvlink/boards/flash.h"
#include "tlvlink/boards/package.h"
#include "tlvlink/boards/strip.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/scene.h"
#include "tlvlink/model.h"
#include "tlvlink/model_integrity.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/quantize/model_sign.h"

namespace tlvlink {
namespace {

const std::string kSource = TLVLINK_SOURCE_DIR;
const std::string kBoards = kSource + "/boards";
const std::string kScenes = kSource + "/boards/scenes";
const std::string kModel = kSource + "/firmware/models/touch-tiny-int8.tlvm";
const char* const kAllScenes[] = {"grasp-two-mini", "material-sort-mini", "surface-log-digit",
                                  "full-two-mini"};

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

TEST(Boards, EveryIssueBoardLoadsWithItsFacts) {
  const std::vector<std::string> names = boards::board_names(kBoards);
  for (const char* n :
       {"rpi4-a72", "rpi5-a76", "jetson-orin-nano", "rk3588", "qemu-virt-a76", "host-x86_64"}) {
    auto b = boards::load_board(kBoards, n);
    ASSERT_TRUE(b.ok()) << b.error().message();
    EXPECT_EQ(b->option("TLVLINK_BOARD"), n);
    EXPECT_GE(b->threads, 1) << n;
    EXPECT_FALSE(b->xnnpack_kernels.empty()) << n;
    if (b->arch == "arm64") {
      EXPECT_TRUE(b->cross) << n;
      EXPECT_FALSE(b->cpu_features.empty()) << n;
    }
  }
  // The A72 build must not need the dot product; every A76-class build must.
  auto pi4 = boards::load_board(kBoards, "rpi4-a72");
  auto pi5 = boards::load_board(kBoards, "rpi5-a76");
  ASSERT_TRUE(pi4.ok() && pi5.ok());
  const auto has = [](const boards::Board& b, const char* f) {
    return std::find(b.cpu_features.begin(), b.cpu_features.end(), f) != b.cpu_features.end();
  };
  EXPECT_FALSE(has(*pi4, "asimddp"));
  EXPECT_TRUE(has(*pi5, "asimddp"));
  EXPECT_EQ(pi5->option("TLVLINK_TARGET_CPU"), "cortex-a76");
  auto rk = boards::load_board(kBoards, "rk3588");
  ASSERT_TRUE(rk.ok());
  EXPECT_EQ(rk->option("TLVLINK_TARGET_CPU"), "cortex-a76.cortex-a55");
  EXPECT_EQ(rk->cpu_affinity, "4-7");
  // Inherited options: qemu-virt-a76 builds on generic-a76's settings.
  auto q = boards::load_board(kBoards, "qemu-virt-a76");
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->option("TLVLINK_TARGET_CPU"), "cortex-a76");
  EXPECT_EQ(q->option("TLVLINK_BUILD_TESTS"), "OFF");
}

TEST(Boards, UnknownBoardIsAnErrorListingTheKnownOnes) {
  auto b = boards::load_board(kBoards, "rpi3");
  ASSERT_FALSE(b.ok());
  const std::string m = b.error().message();
  EXPECT_TRUE(contains(m, "unknown board 'rpi3'")) << m;
  EXPECT_TRUE(contains(m, "rpi5-a76")) << m;
}

TEST(Scenes, EveryShippedSceneMakesAConfigurationTheDaemonAccepts) {
  for (const char* name : kAllScenes) {
    auto s = daemon::find_scene(kScenes, name);
    ASSERT_TRUE(s.ok()) << s.error().message();
    EXPECT_EQ(s->name, name);
    const std::string toml =
        daemon::scene_config_toml(*s, "/usr/share/tlvlink/models/x.tlvm", 2, "test");
    auto c = daemon::parse_config(toml, std::string(name) + " config");
    ASSERT_TRUE(c.ok()) << name << ": " << c.error().message() << "\n" << toml;
    EXPECT_EQ(c->sensors.size(), s->sensors.size());
    EXPECT_EQ(c->processing.contact_gating, s->contact_gating);
    EXPECT_EQ(c->processing.grasp, s->grasp != "off");
    EXPECT_EQ(c->threads, 2);
  }
}

TEST(Scenes, UnknownSceneIsAnErrorListingTheKnownOnes) {
  auto s = daemon::find_scene(kScenes, "juggling");
  ASSERT_FALSE(s.ok());
  const std::string m = s.error().message();
  EXPECT_TRUE(contains(m, "unknown scene 'juggling'")) << m;
  EXPECT_TRUE(contains(m, "grasp-two-mini")) << m;
}

TEST(Scenes, MistakesNameFileLineAndKey) {
  auto bad_key = daemon::parse_scene(
      "heads = []\ncolour = \"red\"\n[[sensor]]\nname = \"a\"\n"
      "model = \"digit\"\ndevice = \"usb:2833:0209\"\n",
      "s.toml");
  ASSERT_FALSE(bad_key.ok());
  EXPECT_TRUE(contains(bad_key.error().message(), "colour")) << bad_key.error().message();
  auto bad_grasp = daemon::parse_scene(
      "grasp = \"detected\"\n[[sensor]]\nname = \"a\"\n"
      "model = \"digit\"\ndevice = \"usb:2833:0209\"\n",
      "g.toml");
  ASSERT_FALSE(bad_grasp.ok());
  EXPECT_TRUE(contains(bad_grasp.error().message(), "g.toml:1: grasp"))
      << bad_grasp.error().message();
  EXPECT_TRUE(contains(bad_grasp.error().message(), "finger A and finger B"));
  auto bad_sensor = daemon::parse_scene(
      "[[sensor]]\nname = \"a\"\nmodel = \"gelsight-max\"\n"
      "device = \"usb:2833:0209\"\n",
      "m.toml");
  ASSERT_FALSE(bad_sensor.ok());
  EXPECT_TRUE(contains(bad_sensor.error().message(), "m.toml:3: sensor[0].model"))
      << bad_sensor.error().message();
}

TEST(Scenes, BuildPlanLeavesOutWhatTheSceneDoesNotUse) {
  auto board = boards::load_board(kBoards, "rpi5-a76");
  auto jsonl = daemon::find_scene(kScenes, "surface-log-digit");
  auto serial = daemon::find_scene(kScenes, "material-sort-mini");
  auto usb = daemon::find_scene(kScenes, "grasp-two-mini");
  ASSERT_TRUE(board.ok() && jsonl.ok() && serial.ok() && usb.ok());
  const auto value = [](const boards::BuildPlan& p, const std::string& name) {
    for (const boards::BuildOption& o : p.options)
      if (o.name == name) return o.value;
    return std::string("unset");
  };
  auto pj = boards::plan_build(*board, *jsonl);
  auto ps = boards::plan_build(*board, *serial);
  auto pu = boards::plan_build(*board, *usb);
  ASSERT_TRUE(pj.ok() && ps.ok() && pu.ok());
  // JSON lines only: no transport, but the protocol library stays (the daemon needs it to
  // build: runtime/stream names its outputs).
  EXPECT_EQ(value(*pj, "TLVLINK_WITH_SERIAL"), "OFF");
  EXPECT_EQ(value(*pj, "TLVLINK_WITH_PROTOCOL"), "ON");
  EXPECT_EQ(value(*pj, "TLVLINK_WITH_USB"), "OFF");
  EXPECT_EQ(value(*ps, "TLVLINK_WITH_SERIAL"), "ON");
  EXPECT_EQ(value(*ps, "TLVLINK_WITH_USB"), "OFF");
  EXPECT_EQ(value(*pu, "TLVLINK_WITH_USB"), "ON");
  for (const auto* p : {&*pj, &*ps, &*pu}) {
    EXPECT_EQ(value(*p, "TLVLINK_BUILD_TESTS"), "OFF");
    EXPECT_EQ(value(*p, "TLVLINK_WITH_LIBCAMERA"), "OFF");
  }
}

TEST(Strip, KeepsOnlyTheScenesHeadsAndStillVerifies) {
  testing::TempDir dir("strip");
  auto scene = daemon::find_scene(kScenes, "grasp-two-mini");
  ASSERT_TRUE(scene.ok());
  auto r = boards::strip_model(kModel, *scene, dir / "grasp.tlvm");
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_TRUE(r->golden_pass);
  EXPECT_EQ(r->golden_after, 1u);
  EXPECT_LT(r->bytes_after, r->bytes_before);
  auto m = Model::load_file((dir / "grasp.tlvm").c_str());
  ASSERT_TRUE(m.ok()) << m.error().message();
  EXPECT_TRUE((*m)->metadata().linear_heads.empty());
  EXPECT_TRUE((*m)->metadata().zero_shot_heads.empty());
  EXPECT_TRUE((*m)->metadata().press_heads.empty()) << "the grasp scene names no press head";
  EXPECT_TRUE((*m)->metadata().grasp_head.present);
  EXPECT_EQ((*m)->metadata().golden.size(), 1u);

  auto sorting = daemon::find_scene(kScenes, "material-sort-mini");
  ASSERT_TRUE(sorting.ok());
  auto s = boards::strip_model(kModel, *sorting, dir / "sort.tlvm");
  ASSERT_TRUE(s.ok()) << s.error().message();
  auto ms = Model::load_file((dir / "sort.tlvm").c_str());
  ASSERT_TRUE(ms.ok());
  ASSERT_EQ((*ms)->metadata().linear_heads.size(), 2u);
  EXPECT_EQ((*ms)->metadata().linear_heads[0].name, "material");
  EXPECT_FALSE((*ms)->metadata().grasp_head.present);

  // The full scene keeps the press head (it names it) and still verifies.
  auto full = daemon::find_scene(kScenes, "full-two-mini");
  ASSERT_TRUE(full.ok());
  auto f = boards::strip_model(kModel, *full, dir / "full.tlvm");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_TRUE(f->golden_pass);
  auto mf = Model::load_file((dir / "full.tlvm").c_str());
  ASSERT_TRUE(mf.ok());
  ASSERT_EQ((*mf)->metadata().press_heads.size(), 1u);
  EXPECT_EQ((*mf)->metadata().press_heads[0].name, "hard_soft_press");
}

TEST(Strip, SceneAskingForAHeadTheModelLacksIsAnErrorNamingIt) {
  testing::TempDir dir("strip_head");
  auto scene = daemon::find_scene(kScenes, "material-sort-mini");
  ASSERT_TRUE(scene.ok());
  scene->heads.push_back("texture");
  auto r = boards::strip_model(kModel, *scene, dir / "x.tlvm");
  ASSERT_FALSE(r.ok());
  const std::string m = r.error().message();
  EXPECT_TRUE(contains(m, "asks for head 'texture'")) << m;
  EXPECT_TRUE(contains(m, "probe:material")) << m;
  EXPECT_FALSE(std::ifstream(dir / "x.tlvm").good()) << "nothing is left behind";
  // Grasps from a model without a grasp head.
  auto sorting = daemon::find_scene(kScenes, "material-sort-mini");
  auto grasp = daemon::find_scene(kScenes, "grasp-two-mini");
  ASSERT_TRUE(sorting.ok() && grasp.ok());
  ASSERT_TRUE(boards::strip_model(kModel, *sorting, dir / "nograsp.tlvm").ok());
  auto g = boards::strip_model(dir / "nograsp.tlvm", *grasp, dir / "y.tlvm");
  ASSERT_FALSE(g.ok());
  EXPECT_TRUE(contains(g.error().message(), "has no grasp head")) << g.error().message();
}

TEST(Strip, ModelWhoseInputTheSensorCannotFeedIsAnErrorNamingTheSensor) {
  testing::TempDir dir("strip_input");
  // The shipped model with a crop larger than a DIGIT's 320x240 view.
  auto model = Model::load_file(kModel.c_str());
  ASSERT_TRUE(model.ok());
  quantize::MetadataSpec spec = quantize::metadata_spec_from((*model)->metadata());
  spec.input.crop_x = 0;
  spec.input.crop_y = 0;
  spec.input.crop_w = 400;
  spec.input.crop_h = 300;
  auto b = quantize::rebuild_with_metadata(**model, spec);
  ASSERT_TRUE(b.ok());
  const std::vector<std::byte> bytes = b->finish();
  std::ofstream(dir / "crop.tlvm", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  auto scene = daemon::find_scene(kScenes, "surface-log-digit");
  ASSERT_TRUE(scene.ok());
  auto r = boards::strip_model(dir / "crop.tlvm", *scene, dir / "out.tlvm");
  ASSERT_FALSE(r.ok());
  const std::string m = r.error().message();
  EXPECT_TRUE(contains(m, "sensor 'probe'")) << m;
  EXPECT_TRUE(contains(m, "cannot feed the model")) << m;
}

// A stripped copy is a new file: unsigned unless a key is given, then signed so a daemon with
// model_public_key accepts it; a signed source without a key is reported, not silently unsigned.
TEST(Strip, SignsTheCopyWithTheGivenKeyAndReportsALostSignature) {
  testing::TempDir dir("strip_sign");
  auto keys = quantize::generate_keypair();
  ASSERT_TRUE(keys.ok());
  ASSERT_TRUE(quantize::write_key_files(dir / "k", *keys).ok());
  auto scene = daemon::find_scene(kScenes, "material-sort-mini");
  ASSERT_TRUE(scene.ok());
  auto r = boards::strip_model(kModel, *scene, dir / "signed.tlvm", dir / "k.key");
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_TRUE(r->signed_copy);
  LoadOptions with_key;
  const PublicKey pub = public_half(keys->secret);
  with_key.public_key = &pub;
  auto m = Model::load_file((dir / "signed.tlvm").c_str(), with_key);
  ASSERT_TRUE(m.ok()) << m.error().message();
  EXPECT_TRUE((*m)->integrity().is_signed);

  // The signed copy stripped again without a key: unsigned, and the lost key is named.
  auto again = boards::strip_model(dir / "signed.tlvm", *scene, dir / "unsigned.tlvm");
  ASSERT_TRUE(again.ok()) << again.error().message();
  EXPECT_FALSE(again->signed_copy);
  EXPECT_EQ(again->source_key_id.size(), 16u);
  auto refused = Model::load_file((dir / "unsigned.tlvm").c_str(), with_key);
  EXPECT_FALSE(refused.ok());

  // A key file that is not one: an error naming it, nothing written.
  std::ofstream(dir / "bad.key") << "not a key\n";
  auto bad = boards::strip_model(kModel, *scene, dir / "x.tlvm", dir / "bad.key");
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(contains(bad.error().message(), "bad.key")) << bad.error().message();
  EXPECT_FALSE(std::ifstream(dir / "x.tlvm").good());
}

// A failed strip leaves what was at the output path untouched (written beside it, renamed last).
TEST(Strip, FailureKeepsTheExistingOutput) {
  testing::TempDir dir("strip_keep");
  auto scene = daemon::find_scene(kScenes, "material-sort-mini");
  ASSERT_TRUE(scene.ok());
  ASSERT_TRUE(boards::strip_model(kModel, *scene, dir / "out.tlvm").ok());
  std::ifstream before_in(dir / "out.tlvm", std::ios::binary);
  const std::string before((std::istreambuf_iterator<char>(before_in)),
                           std::istreambuf_iterator<char>());
  scene->heads.push_back("texture");  // the model has no such head
  ASSERT_FALSE(boards::strip_model(kModel, *scene, dir / "out.tlvm").ok());
  std::ifstream after_in(dir / "out.tlvm", std::ios::binary);
  const std::string after((std::istreambuf_iterator<char>(after_in)),
                          std::istreambuf_iterator<char>());
  EXPECT_EQ(before, after);
}

// The staged root holds what the scene needs (the USB gadget only for USB scenes) and the
// configuration the daemon accepts, pointing at the installed model.
TEST(Package, StagedRootHoldsTheScenesFiles) {
  testing::TempDir dir("stage");
  for (const char* name : {"grasp-two-mini", "material-sort-mini"}) {
    boards::PackageInput in;
    auto b = boards::load_board(kBoards, "host-x86_64");  // strips with the host's strip
    auto s = daemon::find_scene(kScenes, name);
    ASSERT_TRUE(b.ok() && s.ok());
    in.board = *b;
    in.scene = *s;
    in.source_dir = kSource;
    in.daemon_binary = "/bin/true";  // any ELF: staged as it is (stripped)
    in.model_path = kModel;
    const std::string root = dir / name;
    auto files = boards::stage_root(in, root);
    ASSERT_TRUE(files.ok()) << files.error().message();
    const bool usb = std::string(name) == "grasp-two-mini";
    EXPECT_EQ(std::ifstream(root + "/usr/libexec/tlvlink/usb_gadget.sh").good(), usb) << name;
    EXPECT_EQ(std::ifstream(root + "/lib/systemd/system/tlvlink-usb-gadget.service").good(), usb)
        << name;
    EXPECT_TRUE(std::ifstream(root + boards::installed_model_path(in)).good()) << name;
    std::ifstream toml(root + "/etc/tlvlink/tlvlinkd.toml");
    const std::string text((std::istreambuf_iterator<char>(toml)),
                           std::istreambuf_iterator<char>());
    EXPECT_TRUE(contains(text, boards::installed_model_path(in))) << text;
    EXPECT_TRUE(daemon::parse_config(text, name).ok()) << text;
  }
}

// A build tree configured for another -mcpu is refused before anything is built in it: its
// objects would put one CPU's code into another board's package.
TEST(Flash, BuildTreeForAnotherCpuIsRefused) {
  testing::TempDir dir("flash_tree");
  const std::string tree = dir / "tree";
  ASSERT_EQ(std::system(("mkdir -p " + tree).c_str()), 0);
  std::ofstream(tree + "/CMakeCache.txt") << "TLVLINK_TARGET_CPU:STRING=cortex-a72\n";
  boards::FlashOptions o;
  o.board = "rpi5-a76";
  o.scene = "grasp-two-mini";
  o.source_dir = kSource;
  o.out_dir = dir / "out";
  o.build_dir = tree;
  auto r = boards::flash(o);
  ASSERT_FALSE(r.ok());
  const std::string m = r.error().message();
  EXPECT_TRUE(contains(m, "-mcpu=cortex-a72")) << m;
  EXPECT_TRUE(contains(m, "needs -mcpu=cortex-a76")) << m;
  EXPECT_FALSE(std::ifstream(tree + "/build.ninja").good()) << "nothing was configured there";
}

// The package's preinst on a Pi 4 (no asimddp) refuses an A76 build with a message, and accepts
// it on a Pi 5; the Pi 4 build installs on both.
TEST(Package, PreinstRefusesAPackageForAnotherCpu) {
  testing::TempDir dir("preinst");
  std::ifstream in(kSource + "/firmware/package/preinst");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty());
  const auto run = [&](const char* board, const char* cpuinfo) {
    boards::PackageInput p;
    auto b = boards::load_board(kBoards, board);
    auto s = daemon::find_scene(kScenes, "grasp-two-mini");
    EXPECT_TRUE(b.ok() && s.ok());
    p.board = *b;
    p.scene = *s;
    std::ofstream(dir / "preinst") << boards::fill_template(text, p);
    const std::string cmd = "TLVLINK_CPUINFO=" + kSource + "/tests/boards/cpuinfo/" + cpuinfo +
                            " sh " + (dir / "preinst") + " install >" + (dir / "out") + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream o(dir / "out");
    const std::string out((std::istreambuf_iterator<char>(o)), std::istreambuf_iterator<char>());
    return std::make_pair(WEXITSTATUS(rc), out);
  };
  const auto [refused, message] = run("rpi5-a76", "rpi4-a72.txt");
  EXPECT_EQ(refused, 1) << message;
  EXPECT_TRUE(contains(message, "built for rpi5-a76")) << message;
  EXPECT_TRUE(contains(message, "asimddp")) << message;
  EXPECT_EQ(run("rpi5-a76", "rpi5-a76.txt").first, 0);
  EXPECT_EQ(run("rpi4-a72", "rpi5-a76.txt").first, 0);
  EXPECT_EQ(run("rpi4-a72", "rpi4-a72.txt").first, 0);
  EXPECT_EQ(run("rk3588", "rpi4-a72.txt").first, 1);
}

}  // namespace
}  // namespace tlvlink
