#include "h5.h"

#include <cstring>
#include <mutex>

#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"

namespace tlvlink::datasets::h5 {
namespace {

// Longest fixed-length string read (object names are a few dozen bytes).
constexpr size_t kMaxStringBytes = size_t{1} << 20;

Handle vlen_utf8_string() {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

Handle open_dataset(hid_t loc, const char* name) {
  return Handle(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose);
}

Status fail(const std::string& what, const char* action) {
  return Error::make(ErrorCode::kIo, "%s: %s failed: %s", what.c_str(), action,
                     last_error().c_str());
}

// Reads one string from a dataset or attribute of type `ftype` via `read(memtype, buffer)`.
template <typename ReadFn>
Result<std::string> read_string_value(hid_t ftype, const char* name, ReadFn read) {
  TLV_ENSURE(H5Tget_class(ftype) == H5T_STRING, ErrorCode::kFormat, "'%s' is not a string", name);
  if (H5Tis_variable_str(ftype) > 0) {
    Handle mtype = vlen_utf8_string();
    H5Tset_cset(mtype.get(), H5Tget_cset(ftype));
    char* p = nullptr;
    TLV_ENSURE(read(mtype.get(), static_cast<void*>(&p)) >= 0, ErrorCode::kFormat,
               "'%s': read failed: %s", name, last_error().c_str());
    std::string s = p != nullptr ? p : "";
    H5free_memory(p);
    return s;
  }
  const size_t n = H5Tget_size(ftype);
  TLV_ENSURE(n > 0 && n <= kMaxStringBytes, ErrorCode::kFormat, "'%s': string of %zu bytes", name,
             n);
  Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mtype.get(), n);
  H5Tset_cset(mtype.get(), H5Tget_cset(ftype));
  std::vector<char> buf(n + 1, '\0');
  TLV_ENSURE(read(mtype.get(), static_cast<void*>(buf.data())) >= 0, ErrorCode::kFormat,
             "'%s': read failed: %s", name, last_error().c_str());
  return std::string(buf.data(), strnlen(buf.data(), n));
}

herr_t collect_error(unsigned /*n*/, const H5E_error2_t* e, void* data) {
  auto* out = static_cast<std::string*>(data);
  if (e->desc == nullptr || e->desc[0] == '\0') return 0;
  if (out->find(e->desc) != std::string::npos) return 0;
  if (!out->empty()) *out += "; ";
  *out += e->desc;
  return 0;
}

}  // namespace

void Handle::reset() {
  if (id_ >= 0 && closer_ != nullptr) closer_(id_);
  id_ = -1;
}

void quiet() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

std::string last_error() {
  std::string s;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_error, &s);
  H5Eclear2(H5E_DEFAULT);
  return s.empty() ? "unknown HDF5 error" : s;
}

Status write_string(hid_t loc, const char* name, const std::string& value,
                    const std::string& what) {
  Handle type = vlen_utf8_string();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle ds(H5Dcreate2(loc, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) return fail(what, "creating the string");
  const char* p = value.c_str();
  if (H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0)
    return fail(what, "writing the string");
  return {};
}

Status write_u8(hid_t loc, const char* name, uint8_t value, const std::string& what) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle ds(H5Dcreate2(loc, name, H5T_STD_U8LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) return fail(what, "creating the scalar");
  if (H5Dwrite(ds.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    return fail(what, "writing the scalar");
  return {};
}

Status write_image(hid_t loc, const char* name, const RgbImage& image, int32_t deflate_level,
                   const std::string& what) {
  const hsize_t dims[3] = {static_cast<hsize_t>(image.height), static_cast<hsize_t>(image.width),
                           3};
  Handle space(H5Screate_simple(3, dims, nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (deflate_level > 0) {
    // One chunk per image: frames are always read whole.
    if (H5Pset_chunk(dcpl.get(), 3, dims) < 0 ||
        H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate_level)) < 0)
      return fail(what, "setting up deflate");
  }
  Handle ds(H5Dcreate2(loc, name, H5T_STD_U8LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) return fail(what, "creating the image");
  if (H5Dwrite(ds.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, image.rgb.data()) < 0)
    return fail(what, "writing the image");
  return {};
}

Status write_string_attribute(hid_t loc, const char* name, const std::string& value,
                              const std::string& what) {
  Handle type = vlen_utf8_string();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(loc, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) return fail(what, "creating the attribute");
  const char* p = value.c_str();
  if (H5Awrite(attr.get(), type.get(), &p) < 0) return fail(what, "writing the attribute");
  return {};
}

bool exists(hid_t loc, const char* name) { return H5Lexists(loc, name, H5P_DEFAULT) > 0; }

Result<std::string> read_string(hid_t loc, const char* name) {
  TLV_ENSURE(exists(loc, name), ErrorCode::kFormat, "no '%s'", name);
  Handle ds = open_dataset(loc, name);
  TLV_ENSURE(ds.valid(), ErrorCode::kFormat, "'%s' is not a dataset: %s", name,
             last_error().c_str());
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  TLV_ENSURE(H5Sget_simple_extent_npoints(space.get()) == 1, ErrorCode::kFormat,
             "'%s' is not a single string", name);
  Handle ftype(H5Dget_type(ds.get()), H5Tclose);
  return read_string_value(ftype.get(), name, [&](hid_t mtype, void* buf) {
    return H5Dread(ds.get(), mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  });
}

Result<int64_t> read_integer(hid_t loc, const char* name) {
  TLV_ENSURE(exists(loc, name), ErrorCode::kFormat, "no '%s'", name);
  Handle ds = open_dataset(loc, name);
  TLV_ENSURE(ds.valid(), ErrorCode::kFormat, "'%s' is not a dataset: %s", name,
             last_error().c_str());
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  TLV_ENSURE(H5Sget_simple_extent_npoints(space.get()) == 1, ErrorCode::kFormat,
             "'%s' is not a scalar", name);
  Handle ftype(H5Dget_type(ds.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(ftype.get());
  if (cls == H5T_INTEGER) {
    int64_t v = 0;
    TLV_ENSURE(H5Dread(ds.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v) >= 0,
               ErrorCode::kFormat, "'%s': read failed: %s", name, last_error().c_str());
    return v;
  }
  // numpy bools arrive as an enum over int8 (h5py): read it as stored, take the base value.
  TLV_ENSURE(cls == H5T_ENUM, ErrorCode::kFormat, "'%s' is not an integer or bool", name);
  Handle native(H5Tget_native_type(ftype.get(), H5T_DIR_DEFAULT), H5Tclose);
  Handle super(H5Tget_super(ftype.get()), H5Tclose);
  const size_t size = H5Tget_size(native.get());
  TLV_ENSURE(size >= 1 && size <= 8, ErrorCode::kFormat, "'%s': enum of %zu bytes", name, size);
  uint8_t buf[8] = {};
  TLV_ENSURE(H5Dread(ds.get(), native.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0,
             ErrorCode::kFormat, "'%s': read failed: %s", name, last_error().c_str());
  uint64_t u = 0;
  std::memcpy(&u, buf, size);  // little-endian host
  if (H5Tget_sign(super.get()) == H5T_SGN_2 && size < 8 && (u >> (size * 8 - 1)) != 0)
    u |= ~uint64_t{0} << (size * 8);
  return static_cast<int64_t>(u);
}

Status read_image(hid_t loc, const char* name, RgbImage& out) {
  TLV_ENSURE(exists(loc, name), ErrorCode::kFormat, "no '%s'", name);
  Handle ds = open_dataset(loc, name);
  TLV_ENSURE(ds.valid(), ErrorCode::kFormat, "'%s' is not a dataset: %s", name,
             last_error().c_str());
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  hsize_t dims[3] = {};
  TLV_ENSURE(H5Sget_simple_extent_ndims(space.get()) == 3, ErrorCode::kFormat,
             "'%s' is not H x W x 3", name);
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  TLV_ENSURE(dims[2] == 3 && dims[0] >= 1 && dims[1] >= 1 && dims[0] <= image::kMaxJpegSide &&
                 dims[1] <= image::kMaxJpegSide,
             ErrorCode::kFormat,
             "'%s' has shape %llu x %llu x %llu (expected H x W x 3, sides 1..%d)", name,
             static_cast<unsigned long long>(dims[0]), static_cast<unsigned long long>(dims[1]),
             static_cast<unsigned long long>(dims[2]), image::kMaxJpegSide);
  Handle ftype(H5Dget_type(ds.get()), H5Tclose);
  TLV_ENSURE(H5Tget_class(ftype.get()) == H5T_INTEGER && H5Tget_size(ftype.get()) == 1,
             ErrorCode::kFormat, "'%s' is not uint8", name);
  out.height = static_cast<int32_t>(dims[0]);
  out.width = static_cast<int32_t>(dims[1]);
  out.rgb.resize(static_cast<size_t>(dims[0] * dims[1] * 3));
  TLV_ENSURE(
      H5Dread(ds.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.rgb.data()) >= 0,
      ErrorCode::kFormat, "'%s': read failed: %s", name, last_error().c_str());
  return {};
}

bool has_attribute(hid_t loc, const char* name) { return H5Aexists(loc, name) > 0; }

Result<std::string> read_string_attribute(hid_t loc, const char* name) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
  TLV_ENSURE(attr.valid(), ErrorCode::kFormat, "no attribute '%s'", name);
  Handle ftype(H5Aget_type(attr.get()), H5Tclose);
  return read_string_value(ftype.get(), name,
                           [&](hid_t mtype, void* buf) { return H5Aread(attr.get(), mtype, buf); });
}

Result<std::vector<std::string>> root_groups(hid_t file) {
  std::vector<std::string> names;
  auto collect = [](hid_t g, const char* name, const H5L_info_t* /*info*/, void* data) -> herr_t {
    Handle obj(H5Oopen(g, name, H5P_DEFAULT), H5Oclose);
    if (obj.valid() && H5Iget_type(obj.get()) == H5I_GROUP)
      static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    H5Eclear2(H5E_DEFAULT);
    return 0;
  };
  hsize_t idx = 0;
  TLV_ENSURE(H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, &idx, collect, &names) >= 0,
             ErrorCode::kFormat, "cannot list the root groups: %s", last_error().c_str());
  return names;
}

}  // namespace tlvlink::datasets::h5
