// The host's Modbus adapter against a TCP peer that accepts the connection and never answers:
// the constructor's first read times out and it throws, and it must leave no client context
// and no socket behind (the sanitizer tier found the context of `swum log` leaked there:
// docs/reliability.md, "Sanitizers"). And against a libmodbus server whose input registers stop
// at 35, as a board without the electrical port's registers 36..44.
#include "device/modbus_device.h"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iterator>
#include <string>
#include <thread>

#include "modbus_codec.h"

namespace swum::host {
namespace {

std::size_t open_descriptors() {
  const std::filesystem::directory_iterator fds("/proc/self/fd");
  return static_cast<std::size_t>(std::distance(begin(fds), end(fds)));
}

TEST(ModbusDevice, ASilentDeviceIsAnErrorThatLeavesNoSocketOpen) {
  // Listening but never accepting: the kernel completes the connection, nobody reads or replies.
  const int listener = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(listener, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(::bind(listener, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(listener, 4), 0);
  ASSERT_EQ(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(ntohs(address.sin_port));
  const DeviceTimeouts timeouts{std::chrono::milliseconds(100), std::chrono::milliseconds(100)};

  const std::size_t before = open_descriptors();
  for (int attempt = 0; attempt < 3; ++attempt) {
    try {
      ModbusDevice device(endpoint, timeouts);
      ADD_FAILURE() << "a device that never answers was accepted";
    } catch (const DeviceError& e) {
      EXPECT_NE(std::string(e.what()).find("no answer"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(open_descriptors(), before) << "sockets left open by the failed connections";
  ::close(listener);
}

TEST(ModbusDevice, ABoardWithoutTheElectricalRegistersIsReadWithoutThem) {
  namespace input = protocol::modbus::input;
  modbus_t* server = modbus_new_tcp("127.0.0.1", 0);
  ASSERT_NE(server, nullptr);
  modbus_mapping_t* map = modbus_mapping_new(0, 0, protocol::modbus::holding::kCount, input::kCurrentA);
  ASSERT_NE(map, nullptr);
  map->tab_input_registers[input::kState] = 1;  // enabled
  int listener = modbus_tcp_listen(server, 1);
  ASSERT_GE(listener, 0);
  sockaddr_in address{};
  socklen_t length = sizeof address;
  ASSERT_EQ(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
  std::thread serve([&] {
    if (modbus_tcp_accept(server, &listener) < 0) return;
    std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {  // until the client closes the connection
      const int n = modbus_receive(server, query);
      if (n < 0) break;
      if (n > 0) modbus_reply(server, query, n, map);  // a read beyond register 35: exception 02
    }
  });
  {
    const DeviceTimeouts timeouts{std::chrono::milliseconds(2000), std::chrono::milliseconds(2000)};
    ModbusDevice device("tcp://127.0.0.1:" + std::to_string(ntohs(address.sin_port)), timeouts);
    for (int k = 0; k < 2; ++k) {
      const DeviceTelemetry t = device.read();
      EXPECT_EQ(t.state, 1);
      EXPECT_FALSE(t.electrical);
      EXPECT_FALSE(t.stator_temperature_c);
    }
  }
  serve.join();
  ::close(listener);
  modbus_mapping_free(map);
  modbus_close(server);
  modbus_free(server);
}

}  // namespace
}  // namespace swum::host
