// The unit whose compile precompiles the headers every test executable reuses (tests/support's
// CMakeLists.txt, lever_test_headers): it holds nothing else.
