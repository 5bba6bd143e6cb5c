// Simulated datasets written through tools/datasets' writers (sets.h).

#include "tlvlink/sim/sets.h"

#include <functional>
#include <memory>
#include <vector>

#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/io/format.h"
#include "tlvlink/io/progress.h"
#include "tlvlink/sim/batch.h"

namespace tlvlink::sim {
namespace {

template <typename Generator, typename Options>
Result<std::vector<std::unique_ptr<Generator>>> make_generators(const Options& options,
                                                                int threads) {
  std::vector<std::unique_ptr<Generator>> generators;
  for (int t = 0; t < threads; ++t) {
    TLV_ASSIGN_OR_RETURN(auto g, Generator::create(options));
    generators.push_back(std::move(g));
  }
  TLV_ENSURE(!generators.empty(), ErrorCode::kInvalidArgument, "threads %d < 1", threads);
  return generators;
}

// Runs the generators into `writer` with a progress line; finishes the writer.
template <typename Item, typename Generator, typename Writer>
Status run(std::vector<std::unique_ptr<Generator>>& generators, Writer& writer,
           const std::string& label, const std::function<void(const Item&)>& also) {
  const int64_t total = generators[0]->size();
  tools::Progress progress(label, total);
  const std::function<Status(const Item&)> consume = [&](const Item& item) {
    if (also) also(item);
    return writer.write(item);
  };
  Status s = generate_in_order<Item>(generators, total, consume, [&] { progress.add(); });
  if (s.ok()) s = writer.finish();
  progress.finish(tools::human_bytes(static_cast<size_t>(writer.summary().bytes)));
  return s;
}

}  // namespace

Result<datasets::WriteSummary> write_touch_set(const TouchSetJob& job) {
  TLV_ASSIGN_OR_RETURN(auto generators,
                       make_generators<TouchSampleGenerator>(job.generator, job.threads));
  datasets::WriterOptions wo = job.writer;
  wo.generator_json = touch_set_options_json(job.generator);
  TLV_ASSIGN_OR_RETURN(auto writer, job.format == TouchSetFormat::kTouchAndGo
                                        ? datasets::create_tag_writer(job.dir, wo)
                                        : datasets::create_touch100k_writer(job.dir, wo));
  TLV_TRY((run<TouchSample>(generators, *writer, job.progress_label, {})));
  return writer->summary();
}

Result<GraspSetSummary> write_grasp_set(const GraspSetJob& job) {
  TLV_ASSIGN_OR_RETURN(auto generators,
                       make_generators<GraspEpisodeGenerator>(job.generator, job.threads));
  datasets::FeelWriterOptions wo = job.writer;
  wo.generator_json = grasp_set_options_json(job.generator);
  wo.gelsight_live_path = job.generator.live_path;  // no second camera round trip
  TLV_ASSIGN_OR_RETURN(auto writer, job.repacked
                                        ? datasets::create_feel_repacked_writer(job.dir, wo)
                                        : datasets::create_feel_writer(job.dir, wo));
  GraspSetSummary out;
  TLV_TRY(
      (run<GraspEpisode>(generators, *writer, job.progress_label, [&out](const GraspEpisode& e) {
        out.gripping += e.is_gripping ? 1 : 0;
      })));
  out.written = writer->summary();
  return out;
}

}  // namespace tlvlink::sim
