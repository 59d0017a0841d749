# plume_require_package(<name> <version> <debian-package>)
# find_package(<name> <version>) that stops with a message naming the Debian package.
macro(plume_require_package name version debpkg)
  find_package(${name} ${version} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR "plume needs ${name} ${version} or newer, which CMake could not find.\n"
                        "On Debian: apt-get install ${debpkg}   (the README's commands install it for you)")
  endif()
endmacro()
