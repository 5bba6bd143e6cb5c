#pragma once
// MCAP recordings of a listener session (`tlvlink listen --record run.mcap`): the channel table's
// JSON messages (channels.h), which Foxglove opens offline, plus one channel of the raw records
// a .tlvrec would hold (the bytes read from the link with their host times, link up/down, the
// commands sent), so `tlvlink replay run.mcap` feeds the same bytes to the same decoder and
// prints exactly what replaying the .tlvrec of the run prints.
//
// The record channel: topic /tlvlink/records, message encoding "tlvlink.record", no schema; each
// message is one record: kind u8 (listen::RecordKind) then its bytes; log time = the record's
// host time. Foxglove shows it as a topic it cannot decode; it is there for replay.

#include <memory>
#include <string>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/foxglove/mcap_reader.h"
#include "tlvlink/foxglove/mcap_writer.h"
#include "tlvlink/listen/recording.h"
#include "tlvlink/listen/session.h"

namespace tlvlink::foxglove {

inline constexpr std::string_view kRecordTopic = "/tlvlink/records";
inline constexpr std::string_view kRecordEncoding = "tlvlink.record";
inline constexpr uint16_t kRecordChannelId = 100;  // after the channel table's ids

// True for a path whose extension is .mcap (case-insensitive): the recording format is chosen by
// it.
bool is_mcap_path(std::string_view path);

// Both a RecordSink (the client's raw records) and a MessageSink (the session's messages).
class McapRecording : public listen::RecordSink, public listen::MessageSink {
 public:
  // Creates `path` (the recordings' rule: existing files only with `overwrite`, no FIFO or
  // device) and writes the channel table's schemas and channels and the record channel.
  static Result<std::unique_ptr<McapRecording>> create(const std::string& path, bool overwrite);
  Status write(listen::RecordKind kind, int64_t time_ns, std::span<const std::byte> data) override;
  Status flush() override;
  Status on_message(const listen::Message& message, const listen::FormatContext& context) override;
  // Writes the summary and the Footer; the file is complete only after this.
  Status close();
  uint64_t message_count() const { return writer_->message_count(); }
  bool failed() const { return writer_->failed(); }  // a write failed (the session reported it)

 private:
  explicit McapRecording(std::unique_ptr<McapWriter> writer) : writer_(std::move(writer)) {}
  std::unique_ptr<McapWriter> writer_;
  std::vector<std::byte> scratch_;
};

// The record channel of an MCAP recording, for listen::Client::open_replay. An MCAP file without
// it (not written by tlvlink) is an error that says so.
class McapRecordSource : public listen::RecordSource {
 public:
  static Result<std::unique_ptr<McapRecordSource>> open(const std::string& path);
  Result<bool> next(listen::Record& record) override;
  bool truncated() const override { return false; }  // a cut MCAP file does not open

 private:
  explicit McapRecordSource(McapFile file) : file_(std::move(file)) {}
  McapFile file_;
  size_t next_ = 0;
};

}  // namespace tlvlink::foxglove
