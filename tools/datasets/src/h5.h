#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "h5.h is internal to tools/datasets: include its public headers instead"
#endif
// Thin RAII and read/write helpers over the HDF5 C API for the Feel files. HDF5's own error
// printing is switched off; failures come back as messages built from its error stack.
// Internal to tlvlink_datasets.

#include <hdf5.h>

#include <string>
#include <vector>

#include "tlvlink/datasets/records.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets::h5 {

// Owns an HDF5 identifier and closes it with the matching H5*close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      closer_ = o.closer_;
      o.id_ = -1;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset();
  // Gives up ownership (the caller closes the id and checks the result).
  hid_t release() {
    const hid_t id = id_;
    id_ = -1;
    return id;
  }

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

// Switches off HDF5's automatic error printing (once per process).
void quiet();
// The descriptions on HDF5's error stack ("; "-joined, innermost last), then clears it.
std::string last_error();

// Writing (group = a record group). Errors name `what` (file:/group/key).
Status write_string(hid_t loc, const char* name, const std::string& value, const std::string& what);
Status write_u8(hid_t loc, const char* name, uint8_t value, const std::string& what);
Status write_image(hid_t loc, const char* name, const RgbImage& image, int32_t deflate_level,
                   const std::string& what);
Status write_string_attribute(hid_t loc, const char* name, const std::string& value,
                              const std::string& what);

// Reading. kFormat errors say what is wrong (absent key, wrong type/shape).
bool exists(hid_t loc, const char* name);
Result<std::string> read_string(hid_t loc, const char* name);
Result<int64_t> read_integer(hid_t loc, const char* name);  // integer/bool-enum scalar
Status read_image(hid_t loc, const char* name, RgbImage& out);
bool has_attribute(hid_t loc, const char* name);
Result<std::string> read_string_attribute(hid_t loc, const char* name);

// Names of the root's groups, in name order.
Result<std::vector<std::string>> root_groups(hid_t file);

}  // namespace tlvlink::datasets::h5
