#include "jsonl_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "tlvlink/atomic_file.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/pipeline/contact_gate.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::daemon::internal {
namespace {

double ms_between(int64_t from, int64_t to) {
  return from > 0 && to > 0 ? static_cast<double>(to - from) * 1e-6 : -1.0;
}

}  // namespace

Result<JsonlWriter> JsonlWriter::open(const std::string& target, OutputNames names) {
  JsonlWriter w;
  w.names_ = std::move(names);
  w.target_ = "jsonl:" + target;
  if (target == "-") {
    w.fd_ = STDOUT_FILENO;
    return w;
  }
  TLV_TRY(check_jsonl_target(target));
  // O_NONBLOCK: a FIFO put there since the check fails the open at once instead of waiting.
  w.fd_ = ::open(target.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NONBLOCK, 0644);
  TLV_ENSURE(w.fd_ >= 0, ErrorCode::kIo, "output %s: %s", w.target_.c_str(), std::strerror(errno));
  w.owns_fd_ = true;
  struct stat st {};
  TLV_ENSURE(::fstat(w.fd_, &st) == 0 && (S_ISREG(st.st_mode) || S_ISCHR(st.st_mode)),
             ErrorCode::kInvalidArgument, "output %s: not a regular file or character device (%s)",
             w.target_.c_str(), file_type_name(st.st_mode));
  ::fcntl(w.fd_, F_SETFL, ::fcntl(w.fd_, F_GETFL) & ~O_NONBLOCK);
  return w;
}

JsonlWriter::JsonlWriter(JsonlWriter&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)),
      owns_fd_(std::exchange(o.owns_fd_, false)),
      target_(std::move(o.target_)),
      names_(std::move(o.names_)),
      lines_(o.lines_),
      failed_(o.failed_),
      too_long_(o.too_long_),
      last_errno_(o.last_errno_),
      closed_(o.closed_.load()) {}

JsonlWriter::~JsonlWriter() {
  if (owns_fd_ && fd_ >= 0) ::close(fd_);
}

void JsonlWriter::write_line(const LineBuffer& line) {
  if (closed_) return;  // the reader left: nobody to lose records to
  if (line.overflowed()) {
    ++failed_;
    ++too_long_;
    return;
  }
  std::string_view v = line.view();
  while (!v.empty()) {
    const ssize_t n = ::write(fd_, v.data(), v.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EPIPE) {  // SIGPIPE is ignored: the pipe's reader closed it
      closed_ = true;
      return;
    }
    if (n <= 0) {
      ++failed_;
      last_errno_ = n < 0 ? errno : EIO;
      return;
    }
    v.remove_prefix(static_cast<size_t>(n));
  }
  ++lines_;
}

std::string JsonlWriter::problem() const {
  std::string out;
  char text[256];
  if (closed_) {
    std::snprintf(text, sizeof text, "output %s: closed by its reader after %llu line(s)",
                  target_.c_str(), static_cast<unsigned long long>(lines_));
    out = text;
  }
  if (failed_ == 0) return out;
  std::snprintf(text, sizeof text, "%soutput %s: %llu record(s) not written (",
                out.empty() ? "" : "; ", target_.c_str(), static_cast<unsigned long long>(failed_));
  out += text;
  if (last_errno_ != 0) {
    std::snprintf(text, sizeof text, "%llu: %s",
                  static_cast<unsigned long long>(failed_ - too_long_),
                  write_error_text(last_errno_));
    out += text;
  }
  if (too_long_ != 0) {
    std::snprintf(text, sizeof text, "%s%llu: longer than the %zu-byte line buffer",
                  last_errno_ != 0 ? ", " : "", static_cast<unsigned long long>(too_long_),
                  LineBuffer::kCapacity);
    out += text;
  }
  return out + ")";
}

void JsonlWriter::frame(const pipeline::FramePrediction& p, int64_t written_ns) {
  const pipeline::FrameTimes& t = p.times;
  line_.printf("{\"type\":\"frame\",\"sensor\":");
  line_.json_string(names_.sensors[static_cast<size_t>(p.sensor)]);
  // Stages as the stats and the stream name them (run_totals.h).
  line_.printf(
      ",\"seq\":%llu,\"capture_ns\":%lld,\"contact\":\"%s\",\"score_dn\":%.2f,"
      "\"encoded\":%s,\"ms\":{\"dequeue\":%.3f,\"decode\":%.3f,\"queue\":%.3f",
      static_cast<unsigned long long>(p.sequence), static_cast<long long>(t.capture_ns),
      pipeline::contact_state_name(static_cast<pipeline::ContactState>(p.contact_state)),
      static_cast<double>(p.contact_score_dn), p.encoder_ran ? "true" : "false",
      ms_between(t.capture_ns, t.dequeued_ns), ms_between(t.dequeued_ns, t.decoded_ns),
      ms_between(t.decoded_ns, t.gated_ns));
  if (p.encoder_ran) {
    line_.printf(",\"preprocess\":%.3f,\"encoder\":%.3f,\"heads\":%.3f",
                 ms_between(t.gated_ns, t.preprocessed_ns),
                 ms_between(t.preprocessed_ns, t.inferred_ns),
                 ms_between(t.inferred_ns, t.heads_ns));
  }
  line_.printf(",\"total\":%.3f}", ms_between(t.capture_ns, written_ns));
  if (p.head_count > 0) {  // in contact (an open-gel frame encoded for a grasp has none)
    line_.printf(",\"heads\":{");
    for (int32_t k = 0; k < p.head_count; ++k) {
      const pipeline::HeadProbabilities& h = p.heads[static_cast<size_t>(k)];
      const OutputNames::Head& names = names_.heads[static_cast<size_t>(h.head)];
      if (k > 0) line_.put(',');
      line_.json_string(names.name);
      line_.printf(":{\"label\":");
      line_.json_string(names.labels[static_cast<size_t>(h.top)]);
      line_.printf(",\"p\":%.4f,\"probs\":[",
                   static_cast<double>(h.probability[static_cast<size_t>(h.top)]));
      for (int16_t i = 0; i < h.labels; ++i) {
        const auto v = static_cast<double>(h.probability[static_cast<size_t>(i)]);
        if (p.embedding_dim > 0) {  // `embedding = true` (comparisons): the float exactly
          line_.printf("%s%.9g", i > 0 ? "," : "", v);
        } else {
          line_.printf("%s%.4f", i > 0 ? "," : "", v);
        }
      }
      line_.printf("]}");
    }
    line_.put('}');
  }
  if (p.embedding_dim > 0) {  // `embedding = true`: %.9g reads back as the same float
    line_.printf(",\"embedding\":[");
    for (int32_t i = 0; i < p.embedding_dim; ++i)
      line_.printf("%s%.9g", i > 0 ? "," : "",
                   static_cast<double>(p.embedding[static_cast<size_t>(i)]));
    line_.printf("],\"int8\":[");
    for (int32_t i = 0; i < p.int8_count; ++i)
      line_.printf("%s%d", i > 0 ? "," : "", p.int8_values[static_cast<size_t>(i)]);
    line_.put(']');
  }
  line_.printf("}\n");
}

void JsonlWriter::grasp(const pipeline::GraspPrediction& g) {
  line_.printf("{\"type\":\"grasp\",\"id\":%llu,\"head\":",
               static_cast<unsigned long long>(g.grasp_id));
  line_.json_string(names_.grasp_head);
  line_.printf(",\"computed\":%s", g.computed ? "true" : "false");
  if (g.computed) {
    line_.printf(",\"p_success\":%.4f,\"prediction\":\"%s\"", static_cast<double>(g.probability),
                 g.probability >= 0.5f ? "success" : "failure");
  } else {
    line_.printf(",\"reason\":");
    line_.json_string(g.reason.data());
  }
  line_.printf(",\"started_ns\":%lld,\"decided_ns\":%lld,\"frames\":[",
               static_cast<long long>(g.started_ns), static_cast<long long>(g.decided_ns));
  for (int32_t i = 0; i < g.frame_count; ++i) {
    const pipeline::GraspFrameRef& f = g.frames[static_cast<size_t>(i)];
    line_.printf("%s{\"finger\":\"%c\",\"moment\":\"%s\",\"seq\":%llu,\"capture_ns\":%lld}",
                 i > 0 ? "," : "", f.finger == 0 ? 'A' : 'B',
                 heads::moment_name(static_cast<heads::Moment>(f.moment)),
                 static_cast<unsigned long long>(f.sequence), static_cast<long long>(f.capture_ns));
  }
  line_.printf("]}\n");
}

void JsonlWriter::event(const EventRecord& e) {
  line_.printf("{\"type\":\"event\",\"t_ns\":%lld,\"level\":\"%s\",\"sensor\":",
               static_cast<long long>(e.t_ns), e.error ? "error" : "info");
  if (e.sensor >= 0) {
    line_.json_string(names_.sensors[static_cast<size_t>(e.sensor)]);
  } else {
    line_.printf("null");
  }
  line_.printf(",\"text\":");
  line_.json_string(e.text.data());
  line_.printf("}\n");
}

void JsonlWriter::write(const OutputRecord& record, int64_t written_ns) {
  line_.clear();
  if (const auto* p = std::get_if<pipeline::FramePrediction>(&record)) {
    frame(*p, written_ns);
  } else if (const auto* g = std::get_if<pipeline::GraspPrediction>(&record)) {
    grasp(*g);
  } else {
    event(std::get<EventRecord>(record));
  }
  write_line(line_);
}

}  // namespace tlvlink::daemon::internal
