// The translation unit that tests/CMakeLists.txt's pbs_test_pch target needs to make the tests'
// precompiled header; it has no code of its own.
