// swum-emu's exit report (docs/emulator.md, "Exit") from given statistics: every line, exact.
#include <gtest/gtest.h>

#include <string>

#include "app/emu_app.h"

namespace swum::emu {
namespace {

ExitStatistics loop_only() {
  ExitStatistics s;
  s.stopped_by_signal = false;
  s.emulated_s = 12.0;
  s.wall_s = 3.25;
  s.state = AmpState::fault;
  s.fault = FaultCode::command_timeout;
  s.tick_hz = 10000.0;
  s.loop.ticks = 120000;
  s.loop.overruns = 6;
  s.loop.lateness_p50_ns = 1500;
  s.loop.lateness_p99_ns = 12000;
  s.loop.lateness_p999_ns = 45000;
  s.loop.lateness_max_ns = 250000;
  s.loop.compute_mean_ns = 2260.0;
  s.loop.compute_p50_ns = 2000;
  s.loop.compute_p99_ns = 8000;
  s.loop.compute_max_ns = 30000;
  s.loop.commands = 42;
  s.loop.command_p50_ns = 60000;
  s.loop.command_p99_ns = 99000;
  s.loop.command_max_ns = 100000;
  s.resyncs = 2;
  s.commands_applied = 40;
  s.commands_rejected = 3;
  s.queue_full = 1;
  return s;
}

const std::string kLoopLines =
    "swum-emu stopped: duration after 12.000 s emulated in 3.250 s wall; state fault, fault command timeout\n"
    "loop statistics: 120000 ticks at 10000 Hz (12.000 s emulated)\n"
    "  lateness  p50 1.5 us  p99 12.0 us  p99.9 45.0 us  max 250.0 us\n"
    "  compute   mean 2.3 us  p50 2.0 us  p99 8.0 us  max 30.0 us\n"
    "  overruns  6 (0.0050 % of ticks)\n"
    "  commands  42; accept-to-effect p50 60.0 us  p99 99.0 us  max 100.0 us\n"
    "  resyncs   2; commands applied 40, rejected 3 (queue full 1)\n";

void count(DropCounters& drops, Drop reason, int n) {
  for (int i = 0; i < n; ++i) drops.count(reason);
}

TEST(EmuExitReport, LoopAndCommandsOnlyWithoutTransports) { EXPECT_EQ(format_exit_report(loop_only()), kLoopLines); }

TEST(EmuExitReport, StoppedBySignal) {
  ExitStatistics s = loop_only();
  s.stopped_by_signal = true;
  s.state = AmpState::disabled;
  s.fault = FaultCode::none;
  const std::string report = format_exit_report(s);
  EXPECT_EQ(report.substr(0, report.find('\n') + 1),
            "swum-emu stopped: signal after 12.000 s emulated in 3.250 s wall; state disabled, fault none\n");
}

TEST(EmuExitReport, ModbusTcpCountsAndCloses) {
  ModbusStats tcp;
  tcp.requests = 1000;
  tcp.exceptions = 7;
  tcp.connections = 12;
  tcp.receive_errors = 99;  // not in the TCP lines
  count(tcp.drops, Drop::no_slot, 3);
  count(tcp.drops, Drop::evicted, 1);
  count(tcp.drops, Drop::idle, 2);
  count(tcp.drops, Drop::frame_timeout, 4);
  count(tcp.drops, Drop::reply_timeout, 5);
  count(tcp.drops, Drop::bad_header, 6);
  count(tcp.drops, Drop::too_long, 7);
  count(tcp.drops, Drop::bad_crc, 9);  // an RTU reason: not shown for TCP
  ExitStatistics s = loop_only();
  s.modbus_tcp = &tcp;
  EXPECT_EQ(format_exit_report(s),
            kLoopLines + "  modbus    1000 requests, 7 exceptions, 12 connections\n"
                         "  modbus tcp closed: no slot 3, evicted 1, idle 2, frame timeout 4, reply timeout 5, "
                         "bad header 6, too long 7\n");
}

TEST(EmuExitReport, ModbusRtuCountsAndDiscards) {
  ModbusStats rtu;
  rtu.requests = 20;
  rtu.exceptions = 1;
  rtu.receive_errors = 6;
  count(rtu.drops, Drop::other_unit, 2);
  count(rtu.drops, Drop::bad_crc, 3);
  count(rtu.drops, Drop::bad_length, 1);
  count(rtu.drops, Drop::frame_timeout, 4);
  ExitStatistics s = loop_only();
  s.modbus_rtu = &rtu;
  EXPECT_EQ(format_exit_report(s),
            kLoopLines +
                "  modbus    20 requests, 1 exceptions, 6 line errors\n"
                "  modbus rtu discarded: other unit 2, bad crc 3, bad length 1, partial frame 0, frame timeout 4\n");
}

TEST(EmuExitReport, HttpCounts) {
  HttpStats http;
  http.requests = 120;
  http.refused = 7;
  http.stream_events = 3000;
  http.stream_refused = 1;
  http.faults_queued = 4;
  ExitStatistics s = loop_only();
  s.http = &http;
  EXPECT_EQ(format_exit_report(s),
            kLoopLines +
                "  http      120 requests, 7 refused; stream events 3000, streams refused 1; faults queued 4\n");
}

TEST(EmuExitReport, CanCountsAndReceiveAge) {
  CanStats can;
  can.rx_frames = 100;
  can.accepted = 90;
  can.rejected = 10;
  can.rx_errors = 1;
  can.tx_frames = 500;
  can.tx_dropped = 2;
  can.tx_errors = 3;
  can.error_frames = 4;
  can.bus_off = 1;
  can.rx_stamped = 95;
  can.rx_stamp_missing = 4;
  can.rx_stamp_implausible = 1;
  Histogram age;
  age.record(40000);  // one sample: every percentile is that sample (clamped to the max)
  ExitStatistics s = loop_only();
  s.can = &can;
  s.can_receive_age = &age;
  s.can_kernel_drops = 7;
  const std::string can_line =
      "  can       rx 100 (accepted 90, rejected 10, receive errors 1), tx 500 (dropped 2, send errors 3), "
      "error frames 4, bus-off 1\n";
  EXPECT_EQ(format_exit_report(s), kLoopLines + can_line +
                                       "  can rx    kernel timestamps 95, missing 4, implausible 1; kernel drops 7; "
                                       "kernel rx -> read p50 40.0 us  p99 40.0 us  max 40.0 us\n");
  s.can_receive_age = nullptr;  // no histogram: an empty one
  EXPECT_EQ(format_exit_report(s), kLoopLines + can_line +
                                       "  can rx    kernel timestamps 95, missing 4, implausible 1; kernel drops 7; "
                                       "kernel rx -> read p50 0.0 us  p99 0.0 us  max 0.0 us\n");
}

TEST(EmuExitReport, TransportsInOrderModbusThenCan) {
  ModbusStats tcp;
  CanStats can;
  ExitStatistics s = loop_only();
  s.modbus_tcp = &tcp;
  s.can = &can;
  const std::string report = format_exit_report(s);
  const auto modbus = report.find("  modbus    0 requests, 0 exceptions, 0 connections\n");
  const auto closed = report.find("  modbus tcp closed:");
  const auto can_line = report.find("  can       rx 0 ");
  const auto can_rx = report.find("  can rx    kernel timestamps 0,");
  ASSERT_NE(modbus, std::string::npos) << report;
  EXPECT_LT(modbus, closed);
  EXPECT_LT(closed, can_line);
  EXPECT_LT(can_line, can_rx);
  EXPECT_EQ(report.rfind("\n"), report.size() - 1);
}

}  // namespace
}  // namespace swum::emu
