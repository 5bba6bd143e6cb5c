#include "gen/session_names.h"

#include <cinttypes>
#include <cstdio>

#include "gen/rng.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim::internal {
namespace {

constexpr int64_t kSlotSeconds = 600;     // one session per 10-minute slot
constexpr int64_t kEpochDay2022 = 18993;  // days from 1970-01-01 to 2022-01-01

// Civil date from days since 1970-01-01 (H. Hinnant's algorithm, proleptic Gregorian).
void civil_from_days(int64_t z, int64_t& y, int64_t& m, int64_t& d) {
  z += 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const int64_t doe = z - era * 146097;
  const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const int64_t mp = (5 * doy + 2) / 153;
  d = doy - (153 * mp + 2) / 5 + 1;
  m = mp < 10 ? mp + 3 : mp - 9;
  y = yoe + era * 400 + (m <= 2 ? 1 : 0);
}

}  // namespace

std::string session_name(uint64_t seed, int64_t session) {
  const int64_t first_day = kEpochDay2022 + static_cast<int64_t>(mix64(seed ^ 0x5E55ull) % 365);
  Rng rng(derive_seed(seed, {tag(Stream::kSession), static_cast<uint64_t>(session), 0x7133}));
  const int64_t t = first_day * 86400 + session * kSlotSeconds + rng.int_in(0, kSlotSeconds - 1);
  int64_t y = 0, m = 0, d = 0;
  civil_from_days(t / 86400, y, m, d);
  const int64_t s = t % 86400;
  char name[128];  // ample for any int64 fields (the compiler checks the worst case)
  std::snprintf(name, sizeof name,
                "%04" PRId64 "%02" PRId64 "%02" PRId64 "_%02" PRId64 "%02" PRId64 "%02" PRId64, y,
                m, d, s / 3600, s / 60 % 60, s % 60);
  return name;
}

std::string object_name(int32_t class_id, int64_t object_index) {
  const Result<const MaterialClass*> c = material_class(class_id);
  std::string name(c.ok() ? c.value()->name : "object");
  for (char& ch : name) ch = ch == ' ' ? '_' : ch;
  char index[24];
  std::snprintf(index, sizeof index, "_%04" PRId64, object_index);
  return name + index;
}

}  // namespace tlvlink::sim::internal
