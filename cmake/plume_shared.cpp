// The shared library plume_shared (CMakeLists.txt, PLUME_DISPATCH=ON) is the compiled floors
// linked whole; a shared library needs a source of its own, and this is it.
