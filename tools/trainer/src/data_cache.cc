// Loading a Touch100k-format set into the in-memory uint8 cache.

#include "data_cache.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <thread>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/io/progress.h"

namespace tlvlink::trainer {
namespace {

constexpr float kNoTarget = std::numeric_limits<float>::quiet_NaN();

std::string join_phrases(const std::vector<std::string>& phrases) {
  std::string s;
  for (const std::string& p : phrases) s += (s.empty() ? "" : ", ") + p;
  return s;
}

// Decodes and resizes one image into `dst` (height * width * 3 bytes) with the preprocessing's
// own resize (a copy when the sizes agree).
// With keep_turned, a frame of width x height turned (width high, height wide) is copied too,
// and `turned` set.
Status load_resized(const std::string& path, int32_t height, int32_t width, ResizeFilter filter,
                    uint8_t* dst, bool keep_turned = false, uint8_t* turned = nullptr) {
  TLV_ASSIGN_OR_RETURN(tools::Image image, tools::read_jpeg(path));
  TLV_ENSURE(image.channels == 3, ErrorCode::kFormat, "%s: %d channels, expected RGB", path.c_str(),
             image.channels);
  const bool is_turned = keep_turned && image.height == width && image.width == height;
  if (turned != nullptr) *turned = is_turned ? 1 : 0;
  if ((image.height == height && image.width == width) || is_turned) {
    std::copy(image.pixels.begin(), image.pixels.end(), dst);
    return {};
  }
  TLV_ASSIGN_OR_RETURN(const tools::Image sized,
                       image::resize(image.view(), height, width, filter));
  std::copy(sized.pixels.begin(), sized.pixels.end(), dst);
  return {};
}

struct Pending {
  std::string key, sentence, phrases;
  int32_t material = -1, hard = -1, rough = -1;
  float log_force = kNoTarget, friction = kNoTarget;
};

}  // namespace

uint64_t DataCache::fingerprint() const {
  uint64_t h = 0xcbf29ce484222325ull;
  for (const std::string& k : keys) {
    for (char c : k) h = (h ^ static_cast<uint8_t>(c)) * 0x100000001b3ull;
    h = (h ^ 0xffu) * 0x100000001b3ull;
  }
  return h;
}

void channel_stats(const std::vector<uint8_t>& pixels, std::vector<float>& mean,
                   std::vector<float>& std) {
  double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
  const size_t n = pixels.size() / 3;
  for (size_t p = 0; p < n; ++p) {
    for (size_t c = 0; c < 3; ++c) {
      const double v = pixels[p * 3 + c] / 255.0;
      sum[c] += v;
      sq[c] += v * v;
    }
  }
  mean.assign(3, 0.0f);
  std.assign(3, 1.0f);
  for (size_t c = 0; c < 3 && n > 0; ++c) {
    const double m = sum[c] / static_cast<double>(n);
    const double var = std::max(0.0, sq[c] / static_cast<double>(n) - m * m);
    mean[c] = static_cast<float>(m);
    // A constant channel would divide by zero; 1/255 keeps one grey level at unit scale.
    std[c] = static_cast<float>(std::max(std::sqrt(var), 1.0 / 255.0));
  }
}

Result<DataCache> load_cache(const CacheOptions& o) {
  // The datasets' one rule: format by marker files, the recorded split of a generated set
  // (the sidecar), else the hash split by session.
  TLV_ASSIGN_OR_RETURN(const std::optional<datasets::DatasetFormat> format,
                       datasets::probe_dataset_format(o.dir));
  TLV_ENSURE(format == datasets::DatasetFormat::kTouch100k, ErrorCode::kFormat,
             "%s: no %s (not a Touch100k-format directory; `tlvlink sim touch100k -o DIR` makes "
             "one)",
             o.dir.c_str(), datasets::kTouch100kIndex);
  const std::optional<datasets::HashSplit> hash = datasets::split_to_apply(
      o.dir, *format, std::nullopt, datasets::HashSplit{o.test_fraction, 0});
  DataCache cache;
  if (!hash) {
    cache.split_source = "sidecar";
  } else {
    char text[96];
    std::snprintf(text, sizeof(text), "session hash (test fraction %g)", o.test_fraction);
    cache.split_source = text;
  }

  // Pass 1: descriptions and split of every sample (no image I/O).
  datasets::Touch100kLoaderOptions lo;
  lo.load_images = false;
  TLV_ASSIGN_OR_RETURN(auto loader, datasets::open_touch100k(o.dir, lo));
  std::vector<Pending> pending;
  datasets::TouchSample s;
  for (;;) {
    TLV_ASSIGN_OR_RETURN(const bool more, loader->next(s));
    if (!more) break;
    const std::string& key = loader->key();
    bool is_test;
    if (!hash) {
      const datasets::Split recorded = loader->recorded_split();
      TLV_ENSURE(recorded != datasets::Split::kAll, ErrorCode::kFormat,
                 "%s: sample '%s' has no train/test split in %s (%s)", o.dir.c_str(), key.c_str(),
                 datasets::kTouch100kSidecar, loader->report().summary().c_str());
      is_test = recorded == datasets::Split::kTest;
    } else {
      is_test = datasets::hash_split_is_test(s.session, *hash);
    }
    if (is_test != (o.split == SplitChoice::kTest)) {
      ++cache.skipped_other_split;
      continue;
    }
    if (o.max_samples > 0 && static_cast<int64_t>(pending.size()) >= o.max_samples) continue;
    // Labels exist only where the simulator's sidecar recorded the material (class id >= 0).
    const bool labelled = s.material.class_id >= 0;
    const bool touching = labelled && s.contact.in_contact && s.contact.force_n > 0 &&
                          std::isfinite(s.contact.force_n) && s.material.friction > 0;
    if (!s.sensor.empty() &&
        std::find(cache.sensors.begin(), cache.sensors.end(), s.sensor) == cache.sensors.end()) {
      cache.sensors.push_back(s.sensor);
    }
    pending.push_back({key, s.sentence_desc, join_phrases(s.phrases), s.material.class_id,
                       labelled ? (s.material.hard ? 1 : 0) : -1, labelled ? s.material.rough : -1,
                       touching ? static_cast<float>(std::log(s.contact.force_n)) : kNoTarget,
                       touching ? static_cast<float>(s.material.friction) : kNoTarget});
  }
  const char* split_name = o.split == SplitChoice::kTrain ? "train" : "test";
  TLV_ENSURE(!pending.empty(), ErrorCode::kInvalidArgument,
             "%s: no %s samples (%s; %lld in the other split; split from %s)", o.dir.c_str(),
             split_name, loader->report().summary().c_str(),
             static_cast<long long>(cache.skipped_other_split), cache.split_source.c_str());

  cache.height = o.touch_height;
  cache.width = o.touch_width;
  cache.vision_height = o.load_vision ? o.vision_height : 0;
  cache.vision_width = o.load_vision ? o.vision_width : 0;
  const size_t per_sample = cache.touch_stride() + cache.vision_stride();
  const size_t need = per_sample * pending.size();
  TLV_ENSURE(o.max_cache_bytes == 0 || need <= o.max_cache_bytes, ErrorCode::kOutOfMemory,
             "%s: %zu %s samples need %.1f MB of image cache (%zu bytes each), over the limit of "
             "%.1f MB; raise --max-cache-mb or pass --max-samples",
             o.dir.c_str(), pending.size(), split_name, static_cast<double>(need) / 1e6, per_sample,
             static_cast<double>(o.max_cache_bytes) / 1e6);

  // Pass 2: decode + resize in parallel; a missing or corrupt image drops its sample (counted).
  const size_t n = pending.size();
  cache.touch.resize(n * cache.touch_stride());
  cache.vision.resize(n * cache.vision_stride());
  std::vector<uint8_t> ok(n, 0), turned(n, 0);
  std::vector<std::string> problems;
  std::mutex problems_mutex;
  std::atomic<size_t> next{0}, done{0};
  auto work = [&] {
    for (size_t i = next++; i < n; i = next++) {
      Status st =
          load_resized(o.dir + "/touch/" + pending[i].key, cache.height, cache.width, o.resize,
                       cache.touch.data() + i * cache.touch_stride(), o.keep_turned, &turned[i]);
      if (st.ok() && o.load_vision) {
        st = load_resized(o.dir + "/vision/" + pending[i].key, cache.vision_height,
                          cache.vision_width, ResizeFilter::kBilinear,
                          cache.vision.data() + i * cache.vision_stride());
      }
      if (st.ok()) {
        ok[i] = 1;
      } else {
        const std::lock_guard<std::mutex> lock(problems_mutex);
        problems.push_back(st.error().message());
      }
      ++done;
    }
  };
  // Workers decode; this thread only redraws the progress line.
  const unsigned workers = std::max(1u, std::min(o.threads, 8u));
  std::vector<std::thread> threads;
  for (unsigned t = 0; t < workers; ++t) threads.emplace_back(work);
  tools::Progress progress(std::string("loading ") + split_name + " images",
                           static_cast<int64_t>(n));
  while (done.load() < n) {
    progress.set(static_cast<int64_t>(done.load()));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (std::thread& t : threads) t.join();
  progress.set(static_cast<int64_t>(n));
  progress.finish();

  // Compact the good samples (order kept).
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!ok[i]) continue;
    if (kept != i) {
      std::copy_n(cache.touch.begin() + static_cast<std::ptrdiff_t>(i * cache.touch_stride()),
                  cache.touch_stride(),
                  cache.touch.begin() + static_cast<std::ptrdiff_t>(kept * cache.touch_stride()));
      if (o.load_vision) {
        std::copy_n(
            cache.vision.begin() + static_cast<std::ptrdiff_t>(i * cache.vision_stride()),
            cache.vision_stride(),
            cache.vision.begin() + static_cast<std::ptrdiff_t>(kept * cache.vision_stride()));
      }
    }
    cache.turned.push_back(turned[i]);
    cache.keys.push_back(std::move(pending[i].key));
    cache.sentences.push_back(std::move(pending[i].sentence));
    cache.phrase_descs.push_back(std::move(pending[i].phrases));
    cache.material.push_back(pending[i].material);
    cache.hard.push_back(pending[i].hard);
    cache.rough.push_back(pending[i].rough);
    cache.log_force.push_back(pending[i].log_force);
    cache.friction.push_back(pending[i].friction);
    ++kept;
  }
  cache.touch.resize(kept * cache.touch_stride());
  cache.vision.resize(kept * cache.vision_stride());
  cache.touch.shrink_to_fit();
  cache.vision.shrink_to_fit();
  std::sort(cache.sensors.begin(), cache.sensors.end());
  cache.load_summary = loader->report().summary();
  if (!problems.empty()) {
    cache.load_summary += "; " + std::to_string(problems.size()) +
                          " samples dropped for unreadable images (first: " + problems[0] + ")";
  }
  TLV_ENSURE(kept > 0, ErrorCode::kInvalidArgument,
             "%s: none of the %zu %s samples has readable "
             "images (first problem: %s)",
             o.dir.c_str(), n, split_name, problems.empty() ? "-" : problems[0].c_str());
  return cache;
}

}  // namespace tlvlink::trainer
