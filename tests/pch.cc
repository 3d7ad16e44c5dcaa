// The translation unit that makes the test programs' precompiled header (tests/CMakeLists.txt,
// plumb_test_pch): every test program reuses it.
