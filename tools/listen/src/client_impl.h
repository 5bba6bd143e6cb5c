#pragma once
// Internals of listen::Client: the state shared by the live and replay pumps and the frame
// accounting. Not part of the public API.
#ifndef TLVLINK_LISTEN_PRIVATE
#error "client_impl.h is internal to tlvlink_listen"
#endif

#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "tlvlink/listen/client.h"
#include "tlvlink/listen/recording.h"
#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::listen {

struct Client::Impl {
  std::string source;
  ClientOptions options;
  std::unique_ptr<transport::Transport> link;  // live sources
  std::unique_ptr<RecordSource> replay;        // replay sources
  std::unique_ptr<RecordingWriter> recorder;   // --record FILE (.tlvrec)
  RecordSink* sink = nullptr;                  // options.record_sink (borrowed)
  std::optional<Error> record_error;           // the write that failed; recording stopped
  std::unique_ptr<protocol::Deframer> deframer = std::make_unique<protocol::Deframer>();
  std::unique_ptr<protocol::Deframer> sent_deframer;  // replay: the client's own commands
  std::deque<Message> ready;
  bool ended = false;

  // Guarded by mutex: read by stats()/clock()/hello()/send() from other threads.
  mutable std::mutex mutex;
  LinkStats stats;
  protocol::ClockSync clock;
  std::optional<Message> hello;
  std::vector<LinkEvent> events;
  // Encoded commands waiting for the link: the user's (send()) and the client's own (Info,
  // TimeSync). Whole frames, never interleaved: the user's go first.
  std::vector<std::byte> out_user, out_auto;
  uint32_t next_sequence = 0;
  // Every command this client sent (its own and the user's): sequence and header send time. A
  // Pong counts for the clock only when it echoes one of them: on a link shared with another
  // host, a Pong to that host's ping carries its clock's t1 (an offset off by its whole uptime).
  std::vector<std::pair<uint32_t, int64_t>> sent_commands;

  // Link thread only.
  std::vector<uint32_t> internal_sequences;  // the client's own Info / TimeSync: replies consumed
  uint64_t boot_id = 0;
  bool have_boot_id = false, have_sequence = false, version_reported = false;
  uint32_t last_sequence = 0;
  int64_t next_open_ns = 0, next_sync_ns = 0;
  int64_t info_due_ns = 0;  // when to ask for a Hello if none came by itself (0: not needed)
  int backoff_ms = 100;
  int burst_syncs = 0;
  std::string down_reason;
  // Replay pacing.
  std::optional<Record> pending_record;
  int64_t replay_offset_ns = 0;
  bool replay_started = false;

  // client_live.cc
  Status pump_live(int64_t deadline_ns);
  void on_connected();
  void on_disconnected(const Error& why);
  Status queue_own(const protocol::Command& command);
  Status write_pending();
  // client_replay.cc
  Status pump_replay(int64_t deadline_ns);
  // client_frames.cc
  void on_bytes(std::span<const std::byte> bytes, int64_t receive_ns);
  void on_frame(const protocol::ReceivedFrame& frame, int64_t receive_ns);
  void track_sequence(uint32_t sequence);  // with mutex held
  void event(LinkEvent::Kind kind, std::string text, int64_t time_ns);
  bool is_internal(uint32_t sequence) const;
  void note_internal(uint32_t sequence);
  void note_sent(uint32_t sequence, int64_t send_ns);         // with mutex held
  bool sent_by_us(uint32_t sequence, int64_t send_ns) const;  // with mutex held
  void record(RecordKind kind, int64_t time_ns, std::span<const std::byte> data);
};

}  // namespace tlvlink::listen
