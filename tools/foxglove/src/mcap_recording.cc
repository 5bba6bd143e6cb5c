#include "tlvlink/foxglove/mcap_recording.h"

#include <strings.h>

#include "tlvlink/foxglove/channels.h"

namespace tlvlink::foxglove {

bool is_mcap_path(std::string_view path) {
  return path.size() > 5 && strncasecmp(path.data() + path.size() - 5, ".mcap", 5) == 0;
}

Result<std::unique_ptr<McapRecording>> McapRecording::create(const std::string& path,
                                                             bool overwrite) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<McapWriter> w, McapWriter::create(path, overwrite));
  for (const ChannelSpec& c : channel_table()) {
    TLV_TRY(w->add_schema(
        {c.id, std::string(c.schema_name), std::string(kSchemaEncoding), std::string(c.schema)}));
    TLV_TRY(w->add_channel({c.id, c.id, std::string(c.topic), std::string(kMessageEncoding), {}}));
  }
  TLV_TRY(w->add_channel(
      {kRecordChannelId, 0, std::string(kRecordTopic), std::string(kRecordEncoding), {}}));
  TLV_TRY(w->flush());
  return std::unique_ptr<McapRecording>(new McapRecording(std::move(w)));
}

Status McapRecording::write(listen::RecordKind kind, int64_t time_ns,
                            std::span<const std::byte> data) {
  scratch_.assign(1, static_cast<std::byte>(kind));
  scratch_.insert(scratch_.end(), data.begin(), data.end());
  const uint64_t t = static_cast<uint64_t>(std::max<int64_t>(time_ns, 0));
  return writer_->write_message(kRecordChannelId, t, t, scratch_);
}

// Closed chunks are already written; the open one stays in memory until it closes (at most
// McapWriterOptions::chunk_span_ns of messages), so a kill loses at most that much.
Status McapRecording::flush() { return writer_->flush(); }

Status McapRecording::on_message(const listen::Message& message,
                                 const listen::FormatContext& context) {
  std::optional<ChannelMessage> m = to_channel_message(message, context);
  if (!m) return Status();
  return writer_->write_message(m->channel_id, static_cast<uint64_t>(m->log_time_ns),
                                static_cast<uint64_t>(std::max<int64_t>(m->publish_time_ns, 0)),
                                std::as_bytes(std::span(m->json.data(), m->json.size())));
}

Status McapRecording::close() { return writer_->close(); }

Result<std::unique_ptr<McapRecordSource>> McapRecordSource::open(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(McapFile file, read_mcap_file(path));
  const McapChannel* records = file.channel(kRecordChannelId);
  TLV_ENSURE(records != nullptr && records->topic == kRecordTopic &&
                 records->message_encoding == kRecordEncoding,
             ErrorCode::kFormat,
             "%s has no %s channel (%s, id %u): not an MCAP recording of tlvlink listen",
             path.c_str(), std::string(kRecordTopic).c_str(), std::string(kRecordEncoding).c_str(),
             kRecordChannelId);
  return std::unique_ptr<McapRecordSource>(new McapRecordSource(std::move(file)));
}

Result<bool> McapRecordSource::next(listen::Record& record) {
  for (; next_ < file_.messages.size(); ++next_) {
    const McapMessage& m = file_.messages[next_];
    if (m.channel_id != kRecordChannelId) continue;
    TLV_ENSURE(!m.data.empty() && m.data.size() - 1 <= listen::kMaxRecordLength, ErrorCode::kFormat,
               "record message %u on %s: %zu bytes (1 to %zu)", m.sequence,
               std::string(kRecordTopic).c_str(), m.data.size(), listen::kMaxRecordLength + 1);
    record.kind = static_cast<listen::RecordKind>(m.data[0]);
    record.time_ns = static_cast<int64_t>(m.log_time);
    record.data.assign(m.data.begin() + 1, m.data.end());
    ++next_;
    return true;
  }
  return false;
}

}  // namespace tlvlink::foxglove
