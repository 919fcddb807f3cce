// SocketCanBus on whatever kernel runs the unit tests: opening fails with a clear message,
// never a crash (no CAN support at all, or no such interface).
#include <gtest/gtest.h>

#include "socketcan_bus.h"

using namespace swum::io;

TEST(SocketCanBusOpen, MissingInterfaceOrCanSupportIsAClearError) {
  try {
    SocketCanBus bus("swumnosuch0");
    FAIL() << "opened a non-existent interface";
  } catch (const CanOpenError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("swumnosuch0"), std::string::npos) << what;
    const bool clear = what.find("kernel has no CAN support") != std::string::npos ||
                       what.find("no such CAN interface") != std::string::npos;
    EXPECT_TRUE(clear) << what;
    EXPECT_TRUE(e.error_number() == EAFNOSUPPORT || e.error_number() == ENODEV) << e.error_number();
  }
}

TEST(SocketCanBusOpen, BadNamesAreRefusedBeforeTheKernel) {
  EXPECT_THROW(SocketCanBus(""), CanOpenError);
  try {
    SocketCanBus bus("an-interface-name-too-long");
    FAIL();
  } catch (const CanOpenError& e) {
    EXPECT_NE(std::string(e.what()).find("longer than 15"), std::string::npos) << e.what();
  }
}
