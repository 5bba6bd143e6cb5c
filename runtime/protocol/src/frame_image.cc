// FrameImage (minor 2): an encoded picture of one frame and its contact mask, both ways.
#include "protocol_internal.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;

std::span<const uint8_t> bytes_of(const flatbuffers::Vector<uint8_t>* v) {
  return v ? std::span<const uint8_t>(v->data(), v->size()) : std::span<const uint8_t>();
}

}  // namespace

Result<std::span<const std::byte>> encode_payload(const FrameImage& m,
                                                  std::span<std::byte> buffer) {
  constexpr const char* kWhat = "FrameImage";
  const size_t cells = size_t{m.mask_width} * m.mask_height;
  TLV_ENSURE(m.mask.size() == (cells + 7) / 8, ErrorCode::kInvalidArgument,
             "encoding %s: a %ux%u mask needs %zu bytes, got %zu", kWhat, m.mask_width,
             m.mask_height, (cells + 7) / 8, m.mask.size());
  internal::SizeBound bound;
  bound.table(12);
  bound.vector(m.mask.size(), 1);
  bound.vector(m.data.size(), 1);
  return internal::build_payload(kWhat, bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    flatbuffers::Offset<flatbuffers::Vector<uint8_t>> data, mask;
    if (!m.data.empty()) data = fbb.CreateVector(m.data.data(), m.data.size());
    if (!m.mask.empty()) mask = fbb.CreateVector(m.mask.data(), m.mask.size());
    fb::FrameImageBuilder b(fbb);
    b.add_capture_ns(m.capture_ns);
    b.add_frame_sequence(m.frame_sequence);
    b.add_data(data);
    b.add_mask(mask);
    b.add_width(m.width);
    b.add_height(m.height);
    b.add_sensor(m.sensor);
    b.add_kind(static_cast<fb::ImageKind>(m.kind));
    b.add_format(static_cast<fb::ImageFormat>(m.format));
    b.add_contact(m.contact);
    b.add_mask_width(m.mask_width);
    b.add_mask_height(m.mask_height);
    return b.Finish();
  });
}

Result<FrameImage> decode_frame_image(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::FrameImage* r,
                       internal::verified_root<fb::FrameImage>("FrameImage", payload));
  FrameImage m;
  m.sensor = r->sensor();
  m.frame_sequence = r->frame_sequence();
  m.capture_ns = r->capture_ns();
  m.kind = static_cast<ImageKind>(r->kind());
  m.width = r->width();
  m.height = r->height();
  m.format = static_cast<ImageFormat>(r->format());
  m.contact = r->contact();
  m.mask_width = r->mask_width();
  m.mask_height = r->mask_height();
  m.mask = bytes_of(r->mask());
  m.data = bytes_of(r->data());
  return m;
}

}  // namespace tlvlink::protocol
