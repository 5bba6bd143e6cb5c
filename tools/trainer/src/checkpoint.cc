// Checkpoint files: save, load, optimizer state.

#include "checkpoint.h"

#include <torch/serialize/input-archive.h>
#include <torch/serialize/output-archive.h>

#include <sys/stat.h>
#include <cstdio>
#include <sstream>

#include "tlvlink/atomic_file.h"

namespace tlvlink::trainer {

Result<ArchSpec> arch_from_meta(const nlohmann::ordered_json& meta) {
  try {
    const nlohmann::ordered_json& a = meta.at("arch");
    return make_arch(a.at("name").get<std::string>(), a.at("input").at(0).get<int32_t>(),
                     a.at("input").at(1).get<int32_t>(), a.at("embedding_dim").get<int32_t>());
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "checkpoint meta has no usable \"arch\": %s", e.what());
  }
}

Status save_checkpoint(const std::string& path, const TrainState& state,
                       const torch::optim::Optimizer* optimizer) {
  // Serialized in memory, then written with the project's atomic writer (temporary in the same
  // directory, fsync, rename, directory fsync): a crash or a full disk never leaves a torn
  // checkpoint, and the previous one stays until the new one is complete.
  std::ostringstream bytes;
  try {
    torch::serialize::OutputArchive archive;
    archive.write("meta", c10::IValue(state.meta.dump()));
    torch::serialize::OutputArchive student;
    state.student->save(student);
    archive.write("student", student);
    archive.write("logit_scale", state.logit_scale.detach());
    if (state.teacher_embeddings.defined()) {
      archive.write("teacher_embeddings", state.teacher_embeddings);
    }
    if (state.projection) {
      torch::serialize::OutputArchive projection;
      state.projection->save(projection);
      archive.write("projection", projection);
    }
    if (state.heads) {
      torch::serialize::OutputArchive heads;
      state.heads->save(heads);
      archive.write("supervised", heads);
    }
    if (optimizer != nullptr) {
      torch::serialize::OutputArchive opt;
      optimizer->save(opt);
      archive.write("optimizer", opt);
    }
    archive.save_to(bytes);
  } catch (const std::exception& e) {
    return Error::make(ErrorCode::kIo, "writing checkpoint %s: %s", path.c_str(),
                       first_line(e.what()).c_str());
  }
  const std::string data = std::move(bytes).str();
  Status s = write_file_atomic(path.c_str(), std::as_bytes(std::span<const char>(data)));
  if (!s.ok()) return s.error().with_context("writing checkpoint %s", path.c_str());
  return {};
}

Result<TrainState> load_checkpoint(const std::string& path) {
  struct stat st {};
  TLV_ENSURE(::stat(path.c_str(), &st) == 0, ErrorCode::kIo, "checkpoint %s does not exist",
             path.c_str());
  TrainState state;
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(path);
    c10::IValue meta;
    TLV_ENSURE(archive.try_read("meta", meta) && meta.isString(), ErrorCode::kFormat,
               "%s: not a tlvlink checkpoint (no meta record)", path.c_str());
    state.meta = nlohmann::ordered_json::parse(meta.toStringRef());
    TLV_ENSURE(state.meta.value("format", "") == kCheckpointFormat, ErrorCode::kFormat,
               "%s: not a tlvlink checkpoint (format tag '%s')", path.c_str(),
               state.meta.value("format", "").c_str());
    TLV_ENSURE(state.meta.value("version", 0) == kCheckpointVersion, ErrorCode::kFormat,
               "%s: checkpoint version %d; this trainer reads version %d", path.c_str(),
               state.meta.value("version", 0), kCheckpointVersion);
    auto arch = arch_from_meta(state.meta);
    if (!arch.ok()) return arch.error().with_context("%s", path.c_str());
    state.student = EncoderNet(std::move(arch).value());
    torch::serialize::InputArchive student;
    archive.read("student", student);
    state.student->load(student);
    archive.read("logit_scale", state.logit_scale);
    torch::Tensor teacher;
    if (archive.try_read("teacher_embeddings", teacher)) state.teacher_embeddings = teacher;
    torch::serialize::InputArchive projection;
    if (archive.try_read("projection", projection)) {
      const auto in = state.meta.at("teacher_dim").get<int64_t>();
      const auto out = state.meta.at("arch").at("embedding_dim").get<int64_t>();
      state.projection = torch::nn::Linear(in, out);
      state.projection->load(projection);
    }
    torch::serialize::InputArchive heads;
    if (archive.try_read("supervised", heads)) {
      // The contact regression exists when the run's settings ask for it (checkpoints written
      // before it existed have none).
      const bool contact = state.meta.contains("settings") &&
                           state.meta.at("settings").value("contact_weight", 0.0) > 0;
      state.heads =
          SupervisedHeads(state.meta.at("arch").at("embedding_dim").get<int64_t>(), contact);
      state.heads->load(heads);
    }
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: malformed checkpoint meta: %s", path.c_str(),
                       e.what());
  } catch (const std::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: not a readable tlvlink checkpoint: %s",
                       path.c_str(), first_line(e.what()).c_str());
  }
  return state;
}

Status load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer) {
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(path);
    torch::serialize::InputArchive opt;
    TLV_ENSURE(archive.try_read("optimizer", opt), ErrorCode::kFormat,
               "%s: the checkpoint holds no optimizer state", path.c_str());
    optimizer.load(opt);
  } catch (const std::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: optimizer state: %s", path.c_str(),
                       first_line(e.what()).c_str());
  }
  return {};
}

}  // namespace tlvlink::trainer
