// The host of the tests' shared precompiled header (tests/CMakeLists.txt,
// CHATTER_TEST_PCH_HEADERS): compiled once so that every test reuses it.
