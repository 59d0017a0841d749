# cmake -P PlumeIsolateObject.cmake: one instruction set's kernel objects -> one object file
# whose only global symbol is KEEP, the table accessor (see PlumeDispatch.cmake for why).
#   -DOBJECTS=<list> -DOUTPUT=<file> -DSUFFIX=<name>_<isa> -DKEEP=<symbol> -DLINKER=ld -DNM=nm
#   -DOBJCOPY=objcopy -DREADELF=readelf
# 1. ld -r: a relocatable link of the objects, so that each inline function has one copy;
# 2. every defined symbol but the table's renamed <name>.plume_<SUFFIX>: a COMDAT group
#    is merged by its signature's name even when the symbol is local, so a local symbol of the
#    old name would still be merged with the baseline's copy (and its references left pointing
#    into a discarded section). The suffix names the floor's kernels and the set, since two
#    isolated objects of one set must not share a name either;
# 3. every global symbol but the table's made local;
# 4. checks: exactly one global definition left, and no static initializer (.init_array or
#    .ctors would run at load time on every CPU, before any dispatch).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(keep ${KEEP})
set(partial ${OUTPUT}.partial)
run(${LINKER} -r -o ${partial} ${OBJECTS})
# Every defined symbol, local ones included: a COMDAT group's signature can be a local symbol
# of no section's content (GCC's C5/D5 groups of aliased constructors and destructors).
run(${NM} --defined-only --format=posix ${partial})
string(REPLACE "\n" ";" lines "${run_output}")
set(names "")
foreach(line IN LISTS lines)
  # Assembler-local labels (.L...) are no group's signature; a name several translation units
  # define locally is listed once (objcopy refuses a second rename of one name).
  if(line MATCHES "^([^ ]+) [A-Za-z] ")
    set(name ${CMAKE_MATCH_1})
    if(NOT name MATCHES "^\\.L")
      list(APPEND names ${name})
    endif()
  endif()
endforeach()
list(REMOVE_DUPLICATES names)
list(REMOVE_ITEM names ${keep})
set(renames "")
foreach(name IN LISTS names)
  string(APPEND renames "${name} ${name}.plume_${SUFFIX}\n")
endforeach()
file(WRITE ${OUTPUT}.renames "${renames}")
run(${OBJCOPY} --redefine-syms=${OUTPUT}.renames --keep-global-symbol=${keep} ${partial} ${OUTPUT})

run(${NM} --defined-only --extern-only --format=posix ${OUTPUT})
string(STRIP "${run_output}" globals)
if(NOT globals MATCHES "^${keep} [A-Za-z] [^\n]*$")
  message(FATAL_ERROR "${OUTPUT}: the only global symbol must be ${keep}, found:\n${globals}")
endif()
run(${READELF} --section-headers --wide ${OUTPUT})
if(run_output MATCHES "\\.(init_array|ctors)")
  message(FATAL_ERROR "${OUTPUT}: the ${SUFFIX} kernels have a static initializer; it would run "
                      "at load time on every CPU, before the dispatch. Make the data constexpr.")
endif()
file(REMOVE ${partial} ${OUTPUT}.renames)
