// The `tlvlink` binary on hostile or careless input (issue 12), end to end: FIFOs and devices
// where files are expected, out-of-range labels in a sidecar, a set without its index or with
// nothing usable, a file-size limit while replacing a good model. Every run is wrapped in
// `timeout 30` (exit 124 = it hung) besides the CTest timeout.
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "support/cli_run.h"
#include "support/temp_dir.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::run_cli;

CliRun tlvlink(const std::string& args) {
  return run_cli("timeout -k 5 30 " TLVLINK_CLI_BINARY, args);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

bool contains(const CliRun& r, const std::string& text) {
  return r.out.find(text) != std::string::npos;
}

class UntrustedCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("untrusted");
    const std::string d = dir_->path();
    ASSERT_RUN(tlvlink("gen-reference -o " + d + "/int8.tlvm --resolution 96 --calib-frames 2"), 0);
    ASSERT_RUN(tlvlink("gen-reference -o " + d + "/fp32.tlvm --resolution 96 --dtype fp32"), 0);
    ASSERT_RUN(tlvlink("sim touch100k -o " + d +
                       "/t100k --sessions 4 --frames-per-session 3 "
                       "--seed 3"),
               0);
  }
  static void TearDownTestSuite() { delete dir_; }

  static std::string path(const std::string& rel) { return (*dir_) / rel; }
  // A copy of the generated set to damage.
  static std::string copy_set(const std::string& name) {
    fs::remove_all(path(name));
    fs::copy(path("t100k"), path(name), fs::copy_options::recursive);
    return path(name);
  }
  // Sets the material class_id of the first test-split sidecar line; returns its line number.
  static int set_class_id(const std::string& set, int class_id) {
    return set_field(set, "class_id", std::to_string(class_id));
  }
  // Sets `field` (an integer in the file) of the first test-split sidecar line to `value` as
  // written; returns its line number.
  static int set_field(const std::string& set, const std::string& field, const std::string& value) {
    const fs::path sidecar = fs::path(set) / "tlvlink_sim_samples.jsonl";
    std::ifstream in(sidecar);
    std::string line, out;
    int n = 0, changed = 0;
    while (std::getline(in, line)) {
      ++n;
      if (changed == 0 && line.find("\"split\":\"test\"") != std::string::npos) {
        line = std::regex_replace(line, std::regex("\"" + field + "\":-?[0-9]+"),
                                  "\"" + field + "\":" + value,
                                  std::regex_constants::format_first_only);
        changed = n;
      }
      out += line + "\n";
    }
    spit(sidecar, out);
    return changed;
  }

  static testing::TempDir* dir_;
};
testing::TempDir* UntrustedCli::dir_ = nullptr;

TEST_F(UntrustedCli, FifoAsModelOrInputIsNotARegularFile) {
  const std::string fifo = path("fifo");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  CliRun r = tlvlink("inspect " + fifo);
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, fifo + ": not a regular file (FIFO)")) << r.out;
  r = tlvlink("infer " + path("int8.tlvm") + " -i " + fifo);
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, fifo + ": not a regular file (FIFO)")) << r.out;
  r = tlvlink("infer " + path("int8.tlvm") + " -i /dev/zero");
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, "/dev/zero: not a regular file (character device)")) << r.out;
}

// Issue 31 item 5: a FIFO given as a key file or as a Feel set is refused at once, naming it
// (each hung, deaf to SIGTERM). `timeout 30` makes a hang exit 124.
TEST_F(UntrustedCli, FifoAsAKeyOrFeelSetIsRefusedAtOnce) {
  const std::string fifo = path("key_fifo");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string src = TLVLINK_SOURCE_DIR;
  const std::string says = fifo + ": not a regular file (FIFO)";
  for (const std::string& args :
       {"sign " + path("int8.tlvm") + " --key " + fifo + " -o " + path("signed.tlvm"),
        "verify " + path("int8.tlvm") + " --public-key " + fifo,
        "strip " + src +
            "/firmware/models/touch-tiny-int8.tlvm --scene material-sort-mini --scenes-dir " + src +
            "/boards/scenes -o " + path("stripped.tlvm") + " --key " + fifo,
        "flash --board rpi4-a72 --scene material-sort-mini --source " + src + " -o " +
            path("flash") + " --key " + fifo,
        "record --feel " + fifo + " -o " + path("feel.tlvraw")}) {
    CliRun r = tlvlink(args);
    EXPECT_NE(r.exit_code, 124) << "hung: " << args;
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_TRUE(contains(r, says)) << args << ": " << r.out;
  }
}

// A FIFO inside a dataset is one unreadable image: counted and named, the run goes on.
TEST_F(UntrustedCli, FifoAsADatasetImageIsSkippedAndNamed) {
  const std::string set = copy_set("fifo_set");
  fs::path image;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(set) / "touch"))
    if (e.path().extension() == ".jpg") image = e.path();
  ASSERT_FALSE(image.empty());
  fs::remove(image);
  ASSERT_EQ(::mkfifo(image.c_str(), 0600), 0);
  CliRun r = tlvlink("eval " + path("int8.tlvm") + " --touch " + set);
  EXPECT_NE(r.exit_code, 124) << "eval hung on a FIFO";
  EXPECT_TRUE(contains(r, image.string() + ": not a regular file (FIFO)")) << r.out;
}

// Labels are range-checked at load: the sample is skipped and named by file:line, in every
// split mode; -5 is not "unlabelled".
TEST_F(UntrustedCli, SidecarClassIdOutOfRangeIsSkippedWithFileLine) {
  for (int bad : {9999, -5}) {
    const std::string set = copy_set("cls" + std::to_string(bad));
    const int line = set_class_id(set, bad);
    ASSERT_GT(line, 0);
    const std::string where = set + "/tlvlink_sim_samples.jsonl:" + std::to_string(line) + ":";
    for (const std::string extra : {"", " --resplit 0.5"}) {
      CliRun r = tlvlink("eval " + path("int8.tlvm") + " --touch " + set + extra);
      EXPECT_RUN(r, 0);
      EXPECT_TRUE(contains(r, where)) << r.out;
      EXPECT_TRUE(contains(r, "class_id " + std::to_string(bad) + " outside 0..19")) << r.out;
    }
  }
}

// Issue 31 item 9: a label that is not an integer within range as written (4294967299 wrapped
// to the valid class 3, 1.5 and true read as 1, 2^31 printed as -2147483648, rough 7 ended the
// run with exit 2 naming nothing): skipped with file:line and the value as written.
TEST_F(UntrustedCli, SidecarLabelsNotIntegersInRangeAreSkippedWithFileLine) {
  struct Case {
    const char* field;
    const char* value;
    const char* says;
  };
  int k = 0;
  for (const Case& c : {Case{"class_id", "4294967299", "class_id 4294967299 outside 0..19"},
                        Case{"class_id", "2147483648", "class_id 2147483648 outside 0..19"},
                        Case{"class_id", "1.5", "class_id 1.5 is not an integer"},
                        Case{"class_id", "true", "class_id true is not an integer"},
                        Case{"rough", "7", "rough 7 outside -1..1"}}) {
    const std::string set = copy_set("label" + std::to_string(k++));
    const int line = set_field(set, c.field, c.value);
    ASSERT_GT(line, 0) << c.field;
    CliRun r = tlvlink("eval " + path("int8.tlvm") + " --touch " + set);
    EXPECT_RUN(r, 0);
    EXPECT_TRUE(contains(r, set + "/tlvlink_sim_samples.jsonl:" + std::to_string(line) + ":"))
        << r.out;
    EXPECT_TRUE(contains(r, c.says)) << c.value << ": " << r.out;
  }
}

// Item 9: a folder member the tool leaves out because it is not a regular file (a FIFO named
// like a frame, a subfolder) or a dataset image that is a FIFO is named, not skipped unseen.
TEST_F(UntrustedCli, SkippedFifosAndFoldersAreNamed) {
  const std::string imgs = path("imgs");
  fs::remove_all(imgs);
  fs::create_directories(imgs + "/sub");
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(path("t100k") + "/touch")) {
    if (e.path().extension() != ".jpg" || n == 5) continue;
    fs::copy_file(e.path(), imgs + "/" + std::to_string(n++) + ".jpg");
  }
  ASSERT_EQ(n, 5);
  const std::string fifo = imgs + "/9.jpg";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  CliRun r = tlvlink("record --images " + imgs + " -o " + path("imgs.tlvraw") + " --overwrite");
  EXPECT_RUN(r, 0);
  EXPECT_TRUE(contains(r, "skipped " + fifo + ": not a regular file (FIFO)")) << r.out;
  EXPECT_TRUE(contains(r, "skipped " + imgs + "/sub: not a regular file (directory)")) << r.out;
  r = tlvlink("quantize " + path("fp32.tlvm") + " --calib-images " + imgs + " -o " +
              path("imgs.tlvm") + " --calib-count 4 --heldout-count 2");
  EXPECT_NE(r.exit_code, 124) << "quantize hung on a FIFO";
  EXPECT_TRUE(contains(r, fifo + ": not a regular file (FIFO)")) << r.out;

  const std::string set = copy_set("fifo_record");
  fs::path image;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(set) / "touch"))
    if (e.path().extension() == ".jpg") image = e.path();
  fs::remove(image);
  ASSERT_EQ(::mkfifo(image.c_str(), 0600), 0);
  r = tlvlink("record --touch100k " + set + " -o " + path("t100k.tlvraw") + " --overwrite");
  EXPECT_RUN(r, 0);
  EXPECT_TRUE(contains(r, image.string() + ": not a regular file (FIFO)")) << r.out;
}

// Item 9: `sim scenario -o DIR` keeps an earlier scenario's files unless --overwrite.
TEST_F(UntrustedCli, SimScenarioKeepsAnEarlierScenarioUnlessOverwrite) {
  const std::string dir = path("scenario");
  fs::remove_all(dir);
  fs::create_directories(dir);
  spit(dir + "/truth.jsonl", "earlier truth\n");
  const std::string args = "sim scenario -o " + dir + " --sensor digit --grasps 0 --presses 1";
  CliRun r = tlvlink(args);
  EXPECT_RUN(r, 2);  // a usage error, as in `tlvlink record`
  EXPECT_TRUE(contains(r, dir + "/truth.jsonl exists (--overwrite replaces it)")) << r.out;
  EXPECT_EQ(slurp(dir + "/truth.jsonl"), "earlier truth\n");
  EXPECT_FALSE(fs::exists(dir + "/A.tlvraw"));
  r = tlvlink(args + " --overwrite");
  EXPECT_RUN(r, 0);
  EXPECT_NE(slurp(dir + "/truth.jsonl"), "earlier truth\n");
}

// `sim feel` writes one of two layouts; an option of the other one would be silently ignored.
// The JPEG options need --repacked and the HDF5 ones refuse it: each is a usage error naming
// --repacked, and nothing is written.
TEST_F(UntrustedCli, FeelOptionsOfTheOtherLayoutAreUsageErrors) {
  const std::string dir = path("feel-layout");
  const char* wrong_layout[] = {"--jpeg-full-chroma", "--jpeg-quality 90", "--repacked --deflate 3",
                                "--repacked --records-per-file 5", "--repacked --quarter-turns 1"};
  for (const char* options : wrong_layout) {
    fs::remove_all(dir);
    const CliRun r = tlvlink("sim feel -o " + dir + " --objects 1 " + options);
    EXPECT_RUN(r, 2) << options;
    EXPECT_TRUE(contains(r, "--repacked")) << options << ": " << r.out;
    EXPECT_FALSE(fs::exists(dir)) << options;
  }
}

TEST_F(UntrustedCli, QuantizeWithoutDataListIsAnErrorNamingIt) {
  const std::string set = copy_set("nolist");
  fs::remove(fs::path(set) / "data_list.json");
  const std::string counts = " --calib-count 4 --heldout-count 2 -q";
  CliRun r = tlvlink("quantize " + path("fp32.tlvm") + " --calib " + set + " -o " +
                     path("nolist.tlvm") + counts);
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, set + "/data_list.json: not found")) << r.out;
  EXPECT_FALSE(fs::exists(path("nolist.tlvm")));
  // Asked for explicitly, the image files are a source.
  r = tlvlink("quantize " + path("fp32.tlvm") + " --calib-images " + set + " -o " +
              path("nolist.tlvm") + counts);
  EXPECT_RUN(r, 0);
  EXPECT_RUN(tlvlink("quantize " + path("fp32.tlvm") + " --calib " + set + " --calib-images " +
                     set + " -o " + path("x.tlvm")),
             2);
}

// Nothing usable is a data error, exit 1, in quantize and eval alike.
TEST_F(UntrustedCli, AllMalformedSetIsExitOneEverywhere) {
  const std::string set = copy_set("allbad");
  std::string text;
  for (int i = 0; i < 12; ++i) text += "not json\n";
  spit(fs::path(set) / "data_list.json", text);
  CliRun r = tlvlink("quantize " + path("fp32.tlvm") + " --calib " + set + " -o " +
                     path("allbad.tlvm") + " --calib-count 4 --heldout-count 2 -q");
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, set + "/data_list.json:1:")) << r.out;
  // The first 10 problems on stderr; all of them in a report file of tlvlink's own when no
  // --problems FILE is named (none is only counted).
  EXPECT_TRUE(contains(r, "12 load problems (the first 10 above), all in ")) << r.out;
  const size_t at = r.out.find("all in ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string own = r.out.substr(at + 7, r.out.find('\n', at) - at - 7);
  EXPECT_NE(own.find("tlvlink-quantize-problems-"), std::string::npos) << own;
  const std::string own_text = slurp(own);
  EXPECT_EQ(std::count(own_text.begin(), own_text.end(), '\n'), 12) << own_text;
  std::remove(own.c_str());
  const std::string log = path("problems.txt");
  r = tlvlink("eval " + path("int8.tlvm") + " --touch " + set + " --problems " + log);
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, set + "/data_list.json:1:")) << r.out;
  EXPECT_TRUE(contains(r, "12 load problems (the first 10 above), all in " + log)) << r.out;
  const std::string logged = slurp(log);
  EXPECT_EQ(std::count(logged.begin(), logged.end(), '\n'), 12) << logged;
  EXPECT_NE(logged.find(set + "/data_list.json:12: malformed line"), std::string::npos) << logged;
}

// A line far over kMaxLineBytes is skipped and named; the other lines still load.
TEST_F(UntrustedCli, OverLongIndexLineIsSkippedWithFileLine) {
  const std::string set = copy_set("longline");
  const fs::path index = fs::path(set) / "data_list.json";
  const std::string rest = slurp(index);
  spit(index, "{\"img\":\"" + std::string(size_t{3} << 20, 'a') + "\"}\n" + rest);
  CliRun r = tlvlink("quantize " + path("fp32.tlvm") + " --calib " + set + " -o " +
                     path("long.tlvm") + " --calib-count 4 --heldout-count 2 -q");
  EXPECT_RUN(r, 0);
  EXPECT_TRUE(contains(r, index.string() + ":1:")) << r.out.substr(0, 2000);
  EXPECT_TRUE(contains(r, "line longer than 1048576 bytes")) << r.out.substr(0, 2000);
}

// ulimit -f while `quantize -o EXISTING` writes: exit 1 naming the limit, the old model
// byte-identical, no temporary left.
TEST_F(UntrustedCli, FileSizeLimitKeepsTheExistingModel) {
  const std::string out = path("existing.tlvm");
  fs::copy_file(path("int8.tlvm"), out, fs::copy_options::overwrite_existing);
  const std::string before = slurp(out);
  CliRun r = run_cli("bash -c 'ulimit -f 64; exec timeout 30 " TLVLINK_CLI_BINARY,
                     "quantize " + path("fp32.tlvm") + " --calib " + path("t100k") + " -o " + out +
                         " --calib-count 4 --heldout-count 2 -q'");
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, out + ": write failed: file size limit reached")) << r.out;
  EXPECT_EQ(slurp(out), before);
  for (const auto& e : fs::directory_iterator(dir_->path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace tlvlink
