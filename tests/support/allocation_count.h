// Every allocation of a test binary that links swum_test_allocation_count (tests/CMakeLists.txt)
// is counted, so that a test can show that a stretch of real-time code allocates nothing: read
// allocation_count() before and after it. The binary's global operator new is replaced.
#pragma once

namespace swum::test {

long allocation_count();

}  // namespace swum::test
