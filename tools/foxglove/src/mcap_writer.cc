#include "tlvlink/foxglove/mcap_writer.h"

#include <cerrno>

#include "mcap_bytes.h"
#include "tlvlink/atomic_file.h"
#include "tlvlink/crc32.h"
#include "tlvlink/listen/recording.h"

namespace tlvlink::foxglove {

using internal::ByteWriter;

namespace {

std::span<const std::byte> magic() { return std::as_bytes(std::span(kMcapMagic)); }

std::vector<std::byte> schema_content(const McapSchema& s) {
  ByteWriter w;
  w.u16(s.id), w.str(s.name), w.str(s.encoding),
      w.str(s.data);  // data: u32 length + bytes, as a string
  return std::move(w.bytes());
}

std::vector<std::byte> channel_content(const McapChannel& c) {
  ByteWriter w;
  w.u16(c.id), w.u16(c.schema_id), w.str(c.topic), w.str(c.message_encoding);
  ByteWriter m;
  for (const auto& [k, v] : c.metadata) m.str(k), m.str(v);
  w.u32(static_cast<uint32_t>(m.size()));
  w.raw(m.bytes());
  return std::move(w.bytes());
}

void append_record(std::vector<std::byte>& out, uint8_t opcode,
                   std::span<const std::byte> content) {
  ByteWriter w;
  w.u8(opcode), w.u64(content.size());
  out.insert(out.end(), w.bytes().begin(), w.bytes().end());
  out.insert(out.end(), content.begin(), content.end());
}

}  // namespace

McapWriter::McapWriter(std::FILE* file, std::string path, McapWriterOptions options)
    : file_(file), path_(std::move(path)), options_(std::move(options)) {}

McapWriter::~McapWriter() {
  if (!closed_) (void)close();
}

Result<std::unique_ptr<McapWriter>> McapWriter::create(const std::string& path, bool overwrite,
                                                       const McapWriterOptions& options) {
  TLV_ASSIGN_OR_RETURN(std::FILE * f,
                       listen::create_recording_file(path, overwrite, "MCAP recording"));
  std::unique_ptr<McapWriter> w(new McapWriter(f, path, options));
  ByteWriter header;
  header.str(options.profile), header.str(options.library);
  TLV_TRY(w->put(magic(), true));
  TLV_TRY(w->put_record(internal::kHeader, header.bytes(), true));
  TLV_TRY(w->flush());
  return w;
}

Status McapWriter::put(std::span<const std::byte> bytes, bool data_section) {
  if (failed_) return *failed_;
  TLV_ENSURE(!closed_, ErrorCode::kInvalidState, "MCAP recording %s: written after close",
             path_.c_str());
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    failed_ = Error::make(ErrorCode::kIo, "writing MCAP recording %s: %s", path_.c_str(),
                          write_error_text(errno));
    return *failed_;
  }
  position_ += bytes.size();
  if (data_section) data_crc_ = crc32(bytes, data_crc_);
  return Status();
}

Status McapWriter::put_record(uint8_t opcode, std::span<const std::byte> content,
                              bool data_section) {
  std::vector<std::byte> r;
  append_record(r, opcode, content);
  return put(r, data_section);
}

Status McapWriter::add_schema(const McapSchema& s) {
  TLV_ENSURE(s.id != 0 && !schemas_.count(s.id), ErrorCode::kInvalidArgument,
             "MCAP recording %s: schema id %u is 0 or taken", path_.c_str(), s.id);
  schemas_[s.id] = s;
  return put_record(internal::kSchema, schema_content(s), true);
}

Status McapWriter::add_channel(const McapChannel& c) {
  TLV_ENSURE(!channels_.count(c.id), ErrorCode::kInvalidArgument,
             "MCAP recording %s: channel id %u is taken", path_.c_str(), c.id);
  TLV_ENSURE(c.schema_id == 0 || schemas_.count(c.schema_id), ErrorCode::kInvalidArgument,
             "MCAP recording %s: channel %s names schema %u, which was not added", path_.c_str(),
             c.topic.c_str(), c.schema_id);
  channels_[c.id] = c;
  return put_record(internal::kChannel, channel_content(c), true);
}

Status McapWriter::write_message(uint16_t channel_id, uint64_t log_time, uint64_t publish_time,
                                 std::span<const std::byte> data) {
  if (failed_) return *failed_;
  TLV_ENSURE(channels_.count(channel_id), ErrorCode::kInvalidArgument,
             "MCAP recording %s: no channel %u", path_.c_str(), channel_id);
  // A chunk spans a bounded time: a recorder that is killed loses at most that much.
  if (!chunk_.empty() && (chunk_.size() >= options_.chunk_bytes ||
                          std::max(log_time, chunk_end_) - std::min(log_time, chunk_start_) >
                              options_.chunk_span_ns)) {
    TLV_TRY(close_chunk());
  }
  ByteWriter m;
  m.u16(channel_id), m.u32(next_sequence_[channel_id]++), m.u64(log_time), m.u64(publish_time);
  m.raw(data);
  chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
  append_record(chunk_, internal::kMessage, m.bytes());
  chunk_start_ = std::min(chunk_start_, log_time), chunk_end_ = std::max(chunk_end_, log_time);
  first_time_ = std::min(first_time_, log_time), last_time_ = std::max(last_time_, log_time);
  ++channel_counts_[channel_id];
  ++message_count_;
  return Status();
}

// Chunk: start u64, end u64, uncompressed size u64, uncompressed CRC u32, compression "", records
// (u64 length + bytes); then one Message Index per channel: channel u16, (log time, offset) pairs.
Status McapWriter::close_chunk() {
  if (chunk_.empty()) return Status();
  const uint64_t chunk_start = position_;
  ByteWriter c;
  c.u64(chunk_start_), c.u64(chunk_end_), c.u64(chunk_.size()), c.u32(crc32(chunk_)), c.str("");
  c.u64(chunk_.size());
  c.raw(chunk_);
  TLV_TRY(put_record(internal::kChunk, c.bytes(), true));
  const uint64_t chunk_length = position_ - chunk_start;
  ByteWriter offsets;  // channel u16 -> its Message Index's file offset u64
  const uint64_t index_start = position_;
  for (const auto& [channel, entries] : chunk_index_) {
    offsets.u16(channel), offsets.u64(position_);
    ByteWriter mi;
    mi.u16(channel), mi.u32(static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) mi.u64(time), mi.u64(offset);
    TLV_TRY(put_record(internal::kMessageIndex, mi.bytes(), true));
  }
  ByteWriter ci;
  ci.u64(chunk_start_), ci.u64(chunk_end_), ci.u64(chunk_start), ci.u64(chunk_length);
  ci.u32(static_cast<uint32_t>(offsets.size()));
  ci.raw(offsets.bytes());
  ci.u64(position_ - index_start), ci.str(""), ci.u64(chunk_.size()), ci.u64(chunk_.size());
  chunk_indexes_.push_back(std::move(ci.bytes()));
  chunk_.clear(), chunk_index_.clear();
  chunk_start_ = UINT64_MAX, chunk_end_ = 0;
  return flush();
}

Status McapWriter::flush() {
  if (failed_) return *failed_;
  if (std::fflush(file_) != 0) {
    failed_ = Error::make(ErrorCode::kIo, "writing MCAP recording %s: %s", path_.c_str(),
                          write_error_text(errno));
    return *failed_;
  }
  return Status();
}

Status McapWriter::close() {
  if (closed_) return failed_ ? Status(*failed_) : Status();
  Status st = close_chunk();
  ByteWriter end;
  end.u32(data_crc_);
  if (st.ok()) st = put_record(internal::kDataEnd, end.bytes(), false);
  // The summary: each group's offset and length go into a Summary Offset record.
  const uint64_t summary_start = position_;
  std::vector<std::byte> summary;
  ByteWriter groups;
  auto group = [&](uint8_t opcode, auto&& write_group) {
    const uint64_t start = summary_start + summary.size();
    write_group();
    groups.u8(internal::kSummaryOffset), groups.u64(17), groups.u8(opcode), groups.u64(start);
    groups.u64(summary_start + summary.size() - start);
  };
  group(internal::kSchema, [&] {
    for (const auto& [id, s] : schemas_)
      append_record(summary, internal::kSchema, schema_content(s));
  });
  group(internal::kChannel, [&] {
    for (const auto& [id, c] : channels_)
      append_record(summary, internal::kChannel, channel_content(c));
  });
  group(internal::kStatistics, [&] {
    ByteWriter s;
    s.u64(message_count_), s.u16(static_cast<uint16_t>(schemas_.size())),
        s.u32(static_cast<uint32_t>(channels_.size()));
    s.u32(0), s.u32(0),
        s.u32(static_cast<uint32_t>(chunk_indexes_.size()));  // attachments, metadata, chunks
    s.u64(message_count_ ? first_time_ : 0), s.u64(message_count_ ? last_time_ : 0);
    s.u32(static_cast<uint32_t>(channel_counts_.size() * 10));
    for (const auto& [id, n] : channel_counts_) s.u16(id), s.u64(n);
    append_record(summary, internal::kStatistics, s.bytes());
  });
  if (!chunk_indexes_.empty()) {
    group(internal::kChunkIndex, [&] {
      for (const auto& ci : chunk_indexes_) append_record(summary, internal::kChunkIndex, ci);
    });
  }
  const uint64_t offsets_start = summary_start + summary.size();
  summary.insert(summary.end(), groups.bytes().begin(), groups.bytes().end());
  // Footer: summary start u64, summary offset start u64, CRC-32 of the summary through these two
  // fields.
  ByteWriter footer;
  footer.u8(internal::kFooter), footer.u64(20), footer.u64(summary_start),
      footer.u64(offsets_start);
  summary.insert(summary.end(), footer.bytes().begin(), footer.bytes().end());
  ByteWriter crc;
  crc.u32(crc32(summary));
  summary.insert(summary.end(), crc.bytes().begin(), crc.bytes().end());
  summary.insert(summary.end(), magic().begin(), magic().end());
  if (st.ok()) st = put(summary, false);
  if (st.ok()) st = flush();
  closed_ = true;
  if (std::fclose(file_) != 0 && st.ok()) {
    st = Error::make(ErrorCode::kIo, "writing MCAP recording %s: %s", path_.c_str(),
                     write_error_text(errno));
  }
  file_ = nullptr;
  return st;
}

}  // namespace tlvlink::foxglove
