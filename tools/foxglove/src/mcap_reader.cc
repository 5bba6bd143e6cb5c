#include "tlvlink/foxglove/mcap_reader.h"

#include <cstring>
#include <map>

#include "mcap_bytes.h"
#include "tlvlink/crc32.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::foxglove {

using internal::ByteReader;

namespace {

// Parses the records of one section (the file, or a chunk's records) into `file`.
class Parser {
 public:
  Parser(McapFile& file, const std::string& name) : file_(file), name_(name) {}

  Status schema(ByteReader& r) {
    McapSchema s;
    s.id = r.u16("id"), s.name = r.str("name"), s.encoding = r.str("encoding"),
    s.data = r.str("data");
    if (!r.error() && s.id == 0) r.fail("schema id 0 is reserved (no schema)", "id");
    if (r.error()) return *r.error();
    if (const McapSchema* known = file_.schema(s.id)) {
      TLV_ENSURE(known->name == s.name && known->encoding == s.encoding && known->data == s.data,
                 ErrorCode::kFormat,
                 "%s: schema %u defined twice with different contents (the second at offset %llu)",
                 name_.c_str(), s.id, static_cast<unsigned long long>(r.offset()));
      return Status();
    }
    file_.schemas.push_back(std::move(s));
    return Status();
  }

  Status channel(ByteReader& r) {
    McapChannel c;
    c.id = r.u16("id"), c.schema_id = r.u16("schema_id"), c.topic = r.str("topic");
    c.message_encoding = r.str("message_encoding");
    const uint32_t n = r.u32("metadata length");
    ByteReader m(r.bytes(n, "metadata"), r.offset() - n, "Channel");
    while (!r.error() && !m.error() && m.remaining() > 0) {
      std::string k = m.str("metadata key");
      c.metadata.emplace_back(std::move(k), m.str("metadata value"));
    }
    if (r.error()) return *r.error();
    if (m.error()) return *m.error();
    TLV_ENSURE(c.schema_id == 0 || file_.schema(c.schema_id), ErrorCode::kFormat,
               "%s: channel %u (%s) at offset %llu names schema %u, which no earlier Schema record "
               "defines",
               name_.c_str(), c.id, c.topic.c_str(), static_cast<unsigned long long>(r.offset()),
               c.schema_id);
    if (const McapChannel* known = file_.channel(c.id)) {
      TLV_ENSURE(known->topic == c.topic && known->schema_id == c.schema_id &&
                     known->message_encoding == c.message_encoding && known->metadata == c.metadata,
                 ErrorCode::kFormat,
                 "%s: channel %u defined twice with different contents (the second at offset %llu)",
                 name_.c_str(), c.id, static_cast<unsigned long long>(r.offset()));
      return Status();
    }
    file_.channels.push_back(std::move(c));
    return Status();
  }

  Status message(ByteReader& r, uint64_t min_time, uint64_t max_time) {
    McapMessage m;
    const uint64_t at = r.offset();
    m.channel_id = r.u16("channel_id"), m.sequence = r.u32("sequence");
    m.log_time = r.u64("log_time"), m.publish_time = r.u64("publish_time");
    std::span<const std::byte> data = r.bytes(r.remaining(), "data");
    if (r.error()) return *r.error();
    TLV_ENSURE(
        file_.channel(m.channel_id), ErrorCode::kFormat,
        "%s: message at offset %llu is on channel %u, which no earlier Channel record defines",
        name_.c_str(), static_cast<unsigned long long>(at), m.channel_id);
    TLV_ENSURE(m.log_time >= min_time && m.log_time <= max_time, ErrorCode::kFormat,
               "%s: message at offset %llu has log time %llu, outside its chunk's [%llu, %llu]",
               name_.c_str(), static_cast<unsigned long long>(at),
               static_cast<unsigned long long>(m.log_time),
               static_cast<unsigned long long>(min_time),
               static_cast<unsigned long long>(max_time));
    m.data.assign(data.begin(), data.end());
    file_.messages.push_back(std::move(m));
    return Status();
  }

  Status chunk(ByteReader& r) {
    const uint64_t start = r.u64("message_start_time"), end = r.u64("message_end_time");
    const uint64_t size = r.u64("uncompressed_size");
    const uint32_t crc = r.u32("uncompressed_crc");
    const std::string compression = r.str("compression");
    const uint64_t length = r.u64("records length");
    const uint64_t records_at = r.offset();
    std::span<const std::byte> records = r.bytes(length, "records");
    if (r.error()) return *r.error();
    TLV_ENSURE(compression.empty(), ErrorCode::kFormat,
               "%s: chunk at offset %llu is compressed with '%.40s'; this reader reads "
               "uncompressed chunks only",
               name_.c_str(), static_cast<unsigned long long>(records_at), compression.c_str());
    TLV_ENSURE(size == length, ErrorCode::kFormat,
               "%s: chunk at offset %llu: uncompressed_size %llu but %llu bytes of records",
               name_.c_str(), static_cast<unsigned long long>(records_at),
               static_cast<unsigned long long>(size), static_cast<unsigned long long>(length));
    TLV_ENSURE(crc == 0 || crc32(records) == crc, ErrorCode::kFormat,
               "%s: chunk at offset %llu: CRC-32 of its records is %08x, the chunk says %08x",
               name_.c_str(), static_cast<unsigned long long>(records_at), crc32(records), crc);
    TLV_ENSURE(start <= end || records.empty(), ErrorCode::kFormat,
               "%s: chunk at offset %llu: message_start_time after message_end_time", name_.c_str(),
               static_cast<unsigned long long>(records_at));
    return records_in(records, records_at, start, end, /*in_chunk=*/true);
  }

  // Records one after another; `in_chunk`: only Schema, Channel and Message are allowed.
  Status records_in(std::span<const std::byte> bytes, uint64_t base, uint64_t min_time,
                    uint64_t max_time, bool in_chunk) {
    for (size_t pos = 0; pos < bytes.size();) {
      ByteReader head(bytes.subspan(pos), base + pos, "a");
      const uint8_t op = head.u8("opcode");
      const uint64_t length = head.u64("record length");
      if (head.error()) {
        return Error::make(
            ErrorCode::kFormat,
            "%s: record at offset %llu is cut short (%zu bytes left, a record needs 9)",
            name_.c_str(), static_cast<unsigned long long>(base + pos), bytes.size() - pos);
      }
      TLV_ENSURE(length <= bytes.size() - pos - internal::kRecordPrefix, ErrorCode::kFormat,
                 "%s: %s record at offset %llu claims %llu bytes; only %zu remain%s", name_.c_str(),
                 internal::opcode_name(op), static_cast<unsigned long long>(base + pos),
                 static_cast<unsigned long long>(length),
                 bytes.size() - pos - internal::kRecordPrefix, in_chunk ? " in its chunk" : "");
      ByteReader r(bytes.subspan(pos + internal::kRecordPrefix, length),
                   base + pos + internal::kRecordPrefix, internal::opcode_name(op));
      switch (op) {
        case internal::kSchema: TLV_TRY(schema(r)); break;
        case internal::kChannel: TLV_TRY(channel(r)); break;
        case internal::kMessage: TLV_TRY(message(r, min_time, max_time)); break;
        default:  // read_mcap passes only the three kinds above: anything else is in a chunk
          return Error::make(ErrorCode::kFormat,
                             "%s: a %s record (opcode 0x%02x) at offset %llu inside a chunk",
                             name_.c_str(), internal::opcode_name(op), op,
                             static_cast<unsigned long long>(base + pos));
      }
      pos += internal::kRecordPrefix + length;
    }
    return Status();
  }

 private:
  McapFile& file_;
  const std::string& name_;
};

McapStatistics statistics(ByteReader& r) {
  McapStatistics s;
  s.message_count = r.u64("message_count"), s.schema_count = r.u16("schema_count");
  s.channel_count = r.u32("channel_count");
  (void)r.u32("attachment_count"), (void)r.u32("metadata_count");
  s.chunk_count = r.u32("chunk_count");
  s.message_start_time = r.u64("message_start_time"),
  s.message_end_time = r.u64("message_end_time");
  (void)r.bytes(r.u32("channel_message_counts length"), "channel_message_counts");
  return s;
}

// The summary's CRC, checked before its records are read (a damaged summary is named as such,
// not as whatever its damaged records seem to say). Only when the file ends with a Footer and
// the magic; a file that does not is refused later, in order.
Status check_summary_crc(std::span<const std::byte> bytes, const std::string& name,
                         McapFile& file) {
  constexpr size_t kFooterRecord = internal::kRecordPrefix + 20, kMagic = sizeof(kMcapMagic);
  if (bytes.size() < 2 * kMagic + kFooterRecord) return Status();
  const size_t footer = bytes.size() - kMagic - kFooterRecord;
  if (std::memcmp(bytes.data() + bytes.size() - kMagic, kMcapMagic, kMagic) != 0 ||
      static_cast<uint8_t>(bytes[footer]) != internal::kFooter) {
    return Status();
  }
  ByteReader r(bytes.subspan(footer + internal::kRecordPrefix, 20),
               footer + internal::kRecordPrefix, "Footer");
  const uint64_t summary_start = r.u64("summary_start");
  (void)r.u64("summary_offset_start");
  const uint32_t crc = r.u32("summary_crc");
  if (crc == 0) return Status();
  TLV_ENSURE(summary_start <= footer, ErrorCode::kFormat,
             "%s: Footer at offset %zu: summary_start %llu is after the Footer", name.c_str(),
             footer, static_cast<unsigned long long>(summary_start));
  const size_t from = summary_start ? summary_start : footer;
  const uint32_t actual = crc32(bytes.subspan(from, footer + internal::kRecordPrefix + 16 - from));
  TLV_ENSURE(actual == crc, ErrorCode::kFormat,
             "%s: the summary (offsets %zu..%zu) has CRC-32 %08x; the Footer says %08x",
             name.c_str(), from, footer, actual, crc);
  file.summary_crc_checked = true;
  return Status();
}

}  // namespace

const McapChannel* McapFile::channel(uint16_t id) const {
  for (const McapChannel& c : channels) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

const McapSchema* McapFile::schema(uint16_t id) const {
  for (const McapSchema& s : schemas) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

Result<McapFile> read_mcap(std::span<const std::byte> bytes, const std::string& name) {
  const char* n = name.c_str();
  constexpr size_t kMagic = sizeof(kMcapMagic);
  TLV_ENSURE(bytes.size() >= kMagic && std::memcmp(bytes.data(), kMcapMagic, kMagic) == 0,
             ErrorCode::kFormat, "%s is not an MCAP file (no MCAP magic at offset 0)", n);
  McapFile file;
  TLV_TRY(check_summary_crc(bytes, name, file));
  Parser parser(file, name);
  bool header = false, footer = false;
  uint64_t data_end_at = 0;
  size_t pos = kMagic;
  while (pos < bytes.size() && !footer) {
    ByteReader head(bytes.subspan(pos), pos, "a");
    const uint8_t op = head.u8("opcode");
    const uint64_t length = head.u64("record length");
    TLV_ENSURE(!head.error(), ErrorCode::kFormat,
               "%s: record at offset %zu is cut short (%zu bytes left, a record needs 9): no "
               "Footer (the writer did not finish)",
               n, pos, bytes.size() - pos);
    TLV_ENSURE(length <= bytes.size() - pos - internal::kRecordPrefix, ErrorCode::kFormat,
               "%s: %s record at offset %zu claims %llu bytes; only %zu remain", n,
               internal::opcode_name(op), pos, static_cast<unsigned long long>(length),
               bytes.size() - pos - internal::kRecordPrefix);
    TLV_ENSURE(header || op == internal::kHeader, ErrorCode::kFormat,
               "%s: the first record (offset %zu) is a %s (opcode 0x%02x), not a Header", n, pos,
               internal::opcode_name(op), op);
    const uint64_t content_at = pos + internal::kRecordPrefix;
    ByteReader r(bytes.subspan(content_at, length), content_at, internal::opcode_name(op));
    switch (op) {
      case internal::kHeader:
        TLV_ENSURE(!header, ErrorCode::kFormat, "%s: a second Header at offset %zu", n, pos);
        file.profile = r.str("profile"), file.library = r.str("library");
        header = true;
        break;
      case internal::kSchema:
      case internal::kChannel:
      case internal::kMessage:
        TLV_TRY(parser.records_in(bytes.subspan(pos, internal::kRecordPrefix + length), pos, 0,
                                  UINT64_MAX, false));
        break;
      case internal::kChunk: TLV_TRY(parser.chunk(r)); break;
      case internal::kStatistics: {
        const McapStatistics s = statistics(r);
        TLV_ENSURE(!file.statistics, ErrorCode::kFormat,
                   "%s: a second Statistics record at offset %zu", n, pos);
        if (!r.error()) file.statistics = s;
        break;
      }
      case internal::kDataEnd: {
        const uint32_t crc = r.u32("data_section_crc");
        if (!r.error() && crc != 0) {
          const uint32_t actual = crc32(bytes.first(pos));
          TLV_ENSURE(actual == crc, ErrorCode::kFormat,
                     "%s: the data section (offsets 0..%zu) has CRC-32 %08x; its Data End record "
                     "says %08x",
                     n, pos, actual, crc);
          file.data_crc_checked = true;
        }
        data_end_at = pos;
        break;
      }
      case internal::kFooter: {
        const uint64_t summary_start = r.u64("summary_start");
        if (r.error()) break;
        TLV_ENSURE(summary_start == 0 || (summary_start > data_end_at && summary_start <= pos),
                   ErrorCode::kFormat,
                   "%s: Footer at offset %zu: summary_start %llu is not between the Data End and "
                   "the Footer",
                   n, pos, static_cast<unsigned long long>(summary_start));
        footer = true;
        break;
      }
      default: break;  // indexes, attachments, metadata, summary offsets, newer kinds: skipped
    }
    if (r.error()) return *r.error();
    pos = content_at + length;
  }
  TLV_ENSURE(footer, ErrorCode::kFormat,
             "%s: no Footer record: the file ends at offset %zu (the writer did not finish)", n,
             bytes.size());
  TLV_ENSURE(
      bytes.size() - pos == kMagic && std::memcmp(bytes.data() + pos, kMcapMagic, kMagic) == 0,
      ErrorCode::kFormat,
      "%s: the Footer at offset %zu is not followed by the closing MCAP magic and the end of the "
      "file",
      n, pos);
  if (file.statistics) {
    const McapStatistics& s = *file.statistics;
    TLV_ENSURE(
        s.message_count == file.messages.size() && s.channel_count == file.channels.size() &&
            s.schema_count == file.schemas.size(),
        ErrorCode::kFormat,
        "%s: Statistics count %llu messages, %u channels, %u schemas; the file has %zu, %zu, %zu",
        n, static_cast<unsigned long long>(s.message_count), s.channel_count, s.schema_count,
        file.messages.size(), file.channels.size(), file.schemas.size());
  }
  return file;
}

Result<McapFile> read_mcap_file(const std::string& path) {
  auto f = RegularFile::open(path.c_str());
  if (!f.ok()) return f.error().with_context("opening MCAP file");
  // Read whole: tlvlink's recordings are minutes of predictions (~40 kB/s), not camera footage.
  constexpr uint64_t kMaxBytes = uint64_t{1} << 31;
  TLV_ENSURE(f->size() <= kMaxBytes, ErrorCode::kInvalidArgument,
             "MCAP file %s: %llu bytes; this reader takes at most %llu", path.c_str(),
             static_cast<unsigned long long>(f->size()),
             static_cast<unsigned long long>(kMaxBytes));
  std::vector<std::byte> bytes(f->size());
  TLV_TRY(f->read_at(bytes, 0, path.c_str()));
  return read_mcap(bytes, path);
}

}  // namespace tlvlink::foxglove
