#include "protocol_internal.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;
using internal::view;

const fb::Hello* hello(const void* t) { return static_cast<const fb::Hello*>(t); }
const fb::HeadInfo* head_info(const void* t) { return static_cast<const fb::HeadInfo*>(t); }

template <typename V>
size_t size_of(const V* v) {
  return v ? v->size() : 0;
}

}  // namespace

std::string_view HeadInfoView::name() const { return view(head_info(table_)->name()); }
HeadKind HeadInfoView::kind() const { return static_cast<HeadKind>(head_info(table_)->kind()); }
size_t HeadInfoView::label_count() const { return size_of(head_info(table_)->labels()); }
std::string_view HeadInfoView::label(size_t i) const {
  return view(head_info(table_)->labels()->Get(static_cast<flatbuffers::uoffset_t>(i)));
}
float HeadInfoView::accuracy() const { return head_info(table_)->accuracy(); }
float HeadInfoView::majority_rate() const { return head_info(table_)->majority_rate(); }
float HeadInfoView::accuracy_ci_low() const { return head_info(table_)->accuracy_ci_low(); }
float HeadInfoView::accuracy_ci_high() const { return head_info(table_)->accuracy_ci_high(); }
float HeadInfoView::balanced_accuracy() const { return head_info(table_)->balanced_accuracy(); }
float HeadInfoView::baseline_accuracy() const { return head_info(table_)->baseline_accuracy(); }
uint32_t HeadInfoView::groups() const { return head_info(table_)->groups(); }

std::string_view HelloView::device() const { return view(hello(table_)->device()); }
std::string_view HelloView::board() const { return view(hello(table_)->board()); }
std::string_view HelloView::firmware_version() const {
  return view(hello(table_)->firmware_version());
}
uint64_t HelloView::boot_id() const { return hello(table_)->boot_id(); }
uint64_t HelloView::schema_hash() const { return hello(table_)->schema_hash(); }
std::string_view HelloView::model_id() const { return view(hello(table_)->model_id()); }
uint64_t HelloView::model_checksum() const { return hello(table_)->model_checksum(); }
size_t HelloView::sensor_count() const { return size_of(hello(table_)->sensors()); }

SensorInfo HelloView::sensor(size_t i) const {
  const fb::SensorInfo* s = hello(table_)->sensors()->Get(static_cast<flatbuffers::uoffset_t>(i));
  SensorInfo out;
  out.index = s->index();
  out.name = view(s->name());
  out.model = view(s->model());
  out.serial = view(s->serial());
  out.pixel_format = view(s->pixel_format());
  out.width = s->width();
  out.height = s->height();
  out.fps = s->fps();
  return out;
}

size_t HelloView::head_count() const { return size_of(hello(table_)->heads()); }
HeadInfoView HelloView::head(size_t i) const {
  return HeadInfoView(hello(table_)->heads()->Get(static_cast<flatbuffers::uoffset_t>(i)));
}
size_t HelloView::stage_name_count() const { return size_of(hello(table_)->stage_names()); }
std::string_view HelloView::stage_name(size_t i) const {
  return view(hello(table_)->stage_names()->Get(static_cast<flatbuffers::uoffset_t>(i)));
}
uint16_t HelloView::embedding_dim() const { return hello(table_)->embedding_dim(); }
std::string_view HelloView::clock() const { return view(hello(table_)->clock()); }
uint32_t HelloView::max_frame_size() const { return hello(table_)->max_frame_size(); }

Result<HelloView> decode_hello(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Hello* root, internal::verified_root<fb::Hello>("Hello", payload));
  return HelloView(root);
}

}  // namespace tlvlink::protocol
