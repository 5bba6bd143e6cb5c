#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "toml_reader.h is internal to firmware/tlvlinkd"
#endif
// Strict, typed reading of one TOML table: every key must be read (an unknown key is an error
// naming it), every value must have the expected type and range. Errors read
// "FILE:LINE: TABLE.KEY: what is wrong".

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#define TOML_EXCEPTIONS 0
#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include "tlvlink/error.h"

namespace tlvlink::daemon::internal {

// A TOML file read whole: a regular file of at most 1 MiB (a FIFO or device would block or never
// end). `what` names it in errors ("configuration", "scene").
Result<std::string> read_toml_file(const std::string& path, const char* what);

class TableReader {
 public:
  TableReader(const toml::table& table, std::string file, std::string prefix);

  // Optional keys: `out` keeps its value when the key is absent.
  Status text(const char* key, std::string& out);
  Status flag(const char* key, bool& out);
  Status integer(const char* key, int64_t& out, int64_t lo, int64_t hi);
  Status integer32(const char* key, int32_t& out, int32_t lo, int32_t hi);
  Status number(const char* key, double& out, double lo, double hi);
  Status number32(const char* key, float& out, float lo, float hi);
  Status texts(const char* key, std::vector<std::string>& out);
  // One of `choices`; out gets its index.
  Status choice(const char* key, std::initializer_list<const char*> choices, int32_t& out);
  bool has(const char* key) const { return table_.contains(key); }
  bool is_array(const char* key) const {
    const toml::node* n = table_.get(key);
    return n != nullptr && n->is_array();
  }
  // Sub-tables: nullptr when absent; an error when the key is not a table.
  Result<const toml::table*> table(const char* key);
  Result<const toml::array*> array_of_tables(const char* key);

  // After reading: any key not read is an error naming it.
  Status finish() const;

  std::string where(const char* key) const;  // "FILE:LINE: PREFIX.KEY"
  const std::string& file() const { return file_; }
  std::string child(const char* key, int index = -1) const;  // prefix of a sub-table

 private:
  const toml::node* find(const char* key);
  const toml::table& table_;
  std::string file_, prefix_;
  std::set<std::string, std::less<>> read_;
};

}  // namespace tlvlink::daemon::internal
