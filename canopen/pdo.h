// The process data objects (CiA 301 7.2.2): four RPDOs and four TPDOs whose communication
// (0x1400-0x1403, 0x1800-0x1803) and mapping (0x1600-0x1603, 0x1A00-0x1A03) parameters live in the
// dictionary (7.5.2.35-38) and are read again at every use, so a remapping by SDO acts on the
// next frame. Mapped values are packed little-endian by their length (8, 16 or 32 bits), in
// mapping order. Pure: times are passed in; no allocation, no exception after construction.
// The caller decides the NMT state: it calls these only in operational (Table 83).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "can_frame.h"
#include "frame_sink.h"
#include "object_dictionary.h"

namespace swum::canopen {

class Pdos {
 public:
  static constexpr std::size_t kRpdos = 4;
  static constexpr std::size_t kTpdos = 4;
  static constexpr std::size_t kMaxEntries = 8;  // mapping sub-indices 1-8: at most 8 objects in 8 bytes

  // Binds the slots of 0x1400-0x1403, 0x1600-0x1603, 0x1800-0x1803 and 0x1A00-0x1A03; throws
  // std::out_of_range if the dictionary lacks one (load time). The COB-IDs come from the
  // dictionary, which resolved their $NODEID; node_id is kept for the caller's information.
  Pdos(ObjectDictionary& od, std::uint8_t node_id);

  // not_rpdo: no valid RPDO has this frame's identifier (bit 31 of its COB-ID clear, 11-bit).
  // applied: an event-driven RPDO (type 254/255), written now into the dictionary in mapping
  // order through od.write(), so the application's observer sees it. latched: a synchronous one
  // (type 0-240), written at the next on_sync(). length_error: fewer bytes than the mapping
  // (nothing written; counted). CiA 301 7.2.2 and Table 50: "PDO not processed due to length
  // error", EMCY 0x8210, which the caller sends. More bytes than the mapping are allowed: the
  // first bytes are used (CiA 301 7.2.2 lets the consumer use the mapped part; CANopenNode's
  // CO_PDO.c does the same and only flags EMCY 0x8220 "PDO length exceeded", which this slave
  // does not send). refused: a mapped object's write() aborted (a read-only or out-of-range
  // value: the other objects are still written; counted in refused_writes()), or the mapping no
  // longer resolves (nothing written; counted in mapping_errors()).
  enum class RpdoStatus { not_rpdo, applied, latched, length_error, refused };
  RpdoStatus receive(const protocol::CanFrame& frame);

  // A SYNC (decode_sync): first the RPDOs latched since the last SYNC are written, then each valid
  // synchronous TPDO that is due is sampled from the dictionary now and sent: type n (1-240) at
  // every n-th SYNC since reset(), type 0 (acyclic synchronous) at a SYNC when its mapped bytes
  // differ from the last sent. The SYNC counter is not used (no SYNC start value 0x1800 sub 6).
  void on_sync(std::uint8_t counter, FrameSink& out);

  // Event-driven TPDOs (type 254/255): sent when the mapped bytes differ from the last sent (or
  // none was sent since reset()) and the inhibit time (sub 3, 100 µs) has passed since the last,
  // or when the event timer (sub 5, ms, 0 = off) has run out since the last. One check per PDO
  // per call, so after a stall each sends once and times from then on (no burst).
  void poll(std::int64_t now_ns, FrameSink& out);

  // NMT start or reset communication: SYNC counts, last sent bytes and latched RPDOs cleared;
  // event timers start at now_ns.
  void reset(std::int64_t now_ns);

  [[nodiscard]] std::uint64_t length_errors() const { return length_errors_; }
  [[nodiscard]] std::uint64_t refused_writes() const { return refused_writes_; }
  // A valid PDO whose mapping does not resolve (count above 8, an object missing, a length other
  // than the object's 8/16/32 bits, more than 64 bits): not sent or not applied, counted. The
  // dictionary's checks of the mapping procedure normally keep this at 0.
  [[nodiscard]] std::uint64_t mapping_errors() const { return mapping_errors_; }
  [[nodiscard]] std::uint8_t node_id() const { return node_id_; }

 private:
  struct MappingSlots {
    std::size_t count = 0;                           // sub 0
    std::array<std::size_t, kMaxEntries> entries{};  // sub 1-8
  };
  // A mapping resolved against the dictionary at the time of use.
  struct Layout {
    std::size_t count = 0;
    std::array<std::size_t, kMaxEntries> slots{};
    std::array<std::uint8_t, kMaxEntries> bytes{};
    std::size_t total_bytes = 0;
  };
  struct Rpdo {
    std::size_t cob_id = 0;
    std::size_t type = 0;
    MappingSlots mapping;
    bool latched = false;
    protocol::CanFrame latched_frame;
  };
  struct Tpdo {
    std::size_t cob_id = 0;
    std::size_t type = 0;
    std::size_t inhibit = 0;
    std::size_t event_timer = 0;
    MappingSlots mapping;
    bool sent = false;  // since reset() or since the PDO was last seen not valid
    protocol::CanFrame last;
    std::int64_t last_sent_ns = 0;
    unsigned syncs = 0;  // since the last transmission of a type 1-240 PDO
  };

  MappingSlots bind_mapping(std::uint16_t index) const;
  [[nodiscard]] bool resolve(const MappingSlots& mapping, Layout& layout) const;
  [[nodiscard]] bool valid(std::size_t cob_id_slot) const;
  // The frame against the RPDO's mapping now: nothing when it fits (layout resolved), else the
  // status it ends with (refused for a mapping that does not resolve, length_error), counted.
  std::optional<RpdoStatus> misfit(const Rpdo& rpdo, const protocol::CanFrame& frame, Layout& layout);
  RpdoStatus apply(const Rpdo& rpdo, const protocol::CanFrame& frame);
  // Samples the TPDO's mapped objects into `frame` (identifier and length set); false if the
  // mapping does not resolve or maps nothing.
  bool sample(const Tpdo& tpdo, protocol::CanFrame& frame);
  void transmit(Tpdo& tpdo, const protocol::CanFrame& frame, std::int64_t now_ns, FrameSink& out);
  // Valid (COB-ID bit 31 clear); a TPDO seen not valid forgets what it sent, so that it is sent
  // afresh once made valid again (the end of CiA 301's remapping procedure).
  bool active(Tpdo& tpdo);
  static bool same_as_last(const Tpdo& tpdo, const protocol::CanFrame& frame);

  ObjectDictionary& od_;
  std::uint8_t node_id_;
  std::array<Rpdo, kRpdos> rpdos_;
  std::array<Tpdo, kTpdos> tpdos_;
  std::uint64_t length_errors_ = 0;
  std::uint64_t refused_writes_ = 0;
  std::uint64_t mapping_errors_ = 0;
};

}  // namespace swum::canopen
