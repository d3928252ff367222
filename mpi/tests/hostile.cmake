# sphray-mpi against a careless or hostile launch (issue 30), one CASE per ctest test. Every run is
# bounded (TIMEOUT 50 here, the test's TIMEOUT 60 around it): a hang fails the test, it does not
# stall the suite. -D: SPHRAY_MPI, MPIEXEC, MPIEXEC_FLAGS (a list), CASE, WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# Runs COMMAND (a list) in WORK_DIR; sets status, out and err in the caller. A run cut off by the
# timeout fails the test at once.
function(run)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE result
                  OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 50)
  if(NOT result MATCHES "^[0-9]+$")
    message(FATAL_ERROR "${CASE}: did not finish (${result}): ${errors}")
  endif()
  set(status ${result} PARENT_SCOPE)
  set(out "${output}" PARENT_SCOPE)
  set(err "${errors}" PARENT_SCOPE)
endfunction()

# `mpiexec -n 1 sphray-mpi A : -n 1 sphray-mpi B`: two ranks given different arguments, as an
# MPMD launch gives them (and as a node-local file that differs between nodes would).
function(run_mpmd a b)
  separate_arguments(a UNIX_COMMAND "${a}")
  separate_arguments(b UNIX_COMMAND "${b}")
  run(${MPIEXEC} ${MPIEXEC_FLAGS} -n 1 ${SPHRAY_MPI} ${a} : -n 1 ${SPHRAY_MPI} ${b})
  set(status ${status} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

function(run_np ranks)
  run(${MPIEXEC} ${MPIEXEC_FLAGS} -n ${ranks} ${SPHRAY_MPI} ${ARGN})
  set(status ${status} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

# The last run ended with exit status expected and said words on stderr, once.
function(expect expected words)
  if(NOT status EQUAL expected)
    message(FATAL_ERROR "${CASE}: status ${status}, expected ${expected}: ${err}")
  endif()
  if(words STREQUAL "")
    return()
  endif()
  string(FIND "${err}" "${words}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${CASE}: no '${words}' in: ${err}")
  endif()
  string(REPLACE "${words}" "" rest "${err}")
  string(FIND "${rest}" "${words}" again)
  if(NOT again EQUAL -1 OR err MATCHES "MPI_ABORT|bad_alloc")
    message(FATAL_ERROR "${CASE}: expected one message, without an abort: ${err}")
  endif()
endfunction()

function(expect_same_file a b)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${a} ${b} RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    file(SIZE ${a} size)
    message(FATAL_ERROR "${CASE}: ${a} changed (now ${size} bytes)")
  endif()
endfunction()

# A small particle file for the cases that read one.
function(make_particles name spheres)
  run_np(1 generate random:${spheres} -o ${name})
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${CASE}: generate random:${spheres} failed (${status}): ${err}")
  endif()
endfunction()

if(CASE STREQUAL "disagree.bench_rays")
  # Was: "double free or corruption" (batches of different lengths reduced together).
  make_particles(good.sphp 2000)
  run_mpmd("bench good.sphp --rays 10000" "bench good.sphp --rays 20000")
  expect(2 "the ranks' input differs in --rays (10000 to 20000)")
elseif(CASE STREQUAL "disagree.bench_file")
  make_particles(a.sphp 2000)
  make_particles(b.sphp 3000)
  run_mpmd("bench a.sphp" "bench b.sphp")
  expect(2 "the ranks read different files (they differ in the particle count (2000 to 3000)")
elseif(CASE STREQUAL "disagree.render_size")
  # Was: a hang (tiles of different sizes).
  run_mpmd("render -s single -W 64 -H 48 -o out.png" "render -s single -W 32 -H 48 -o out.png")
  expect(2 "the ranks' input differs in the image width (32 to 64)")
  if(EXISTS ${WORK_DIR}/out.png)
    message(FATAL_ERROR "${CASE}: an image was written")
  endif()
elseif(CASE STREQUAL "disagree.render_scene")
  # Was: an image mixed from both scenes, exit 0.
  run_mpmd("render -s single -m path -W 32 -H 24 -o out.png"
           "render -s three -m path -W 32 -H 24 -o out.png")
  expect(2 "differs in the scene's sphere count (1 to 3), the scene (hash of its spheres")
  if(EXISTS ${WORK_DIR}/out.png)
    message(FATAL_ERROR "${CASE}: an image was written")
  endif()
elseif(CASE STREQUAL "disagree.subcommand")
  make_particles(good.sphp 100)
  run_mpmd("render -s single -W 8 -H 8 -o out.png" "bench good.sphp")
  expect(2 "the ranks' input differs in the subcommand (or --help)")
elseif(CASE STREQUAL "disagree.parse")
  # One rank's arguments are refused: every rank stops, with that rank's reason.
  run_mpmd("render -s single -W 8 -H 8 -o out.png" "render -s single -W 0 -H 8 -o out.png")
  expect(2 "rank 1: --width: Value 0 not in range")
elseif(CASE MATCHES "^bench_out_of_memory\\.np([0-9]+)$")
  # Reading 4,000,000 particles fits in 300 MB of address space, building their trees does not.
  # Was: std::bad_alloc from every rank and an MPI_ABORT banner.
  set(ranks ${CMAKE_MATCH_1})
  make_particles(big.sphp 4000000)
  math(EXPR share "4000000 / ${ranks}")
  run(prlimit --as=300000000 ${MPIEXEC} ${MPIEXEC_FLAGS} -n ${ranks} ${SPHRAY_MPI} bench big.sphp
      --rays 1000)
  file(REMOVE ${WORK_DIR}/big.sphp)
  expect(1 "big.sphp: out of memory building rank 0's tree over ${share} spheres")
elseif(CASE MATCHES "^fifo\\.np([0-9]+)$")
  # Was: a hang, every rank blocked in open() waiting for a writer.
  set(ranks ${CMAKE_MATCH_1})
  execute_process(COMMAND mkfifo ${WORK_DIR}/f.sphp RESULT_VARIABLE made)
  if(NOT made EQUAL 0)
    message(FATAL_ERROR "${CASE}: mkfifo failed")
  endif()
  execute_process(COMMAND ${MPIEXEC} ${MPIEXEC_FLAGS} -n ${ranks} ${SPHRAY_MPI} bench f.sphp
                  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE status ERROR_VARIABLE err
                  OUTPUT_QUIET TIMEOUT 50)
  if(NOT status MATCHES "^[0-9]+$")
    # Let ranks stuck in open() go (a writer that closes at once), so none outlives the test.
    execute_process(COMMAND timeout 5 sh -c ": > f.sphp" WORKING_DIRECTORY ${WORK_DIR})
    message(FATAL_ERROR "${CASE}: hung on the FIFO (${status})")
  endif()
  expect(2 "f.sphp: not a regular file (a FIFO")
elseif(CASE STREQUAL "generate.full_disk")
  # A file system that fills up part-way through the write (a 64 KiB tmpfs, mounted for the
  # test: root only) must leave the file generate would replace as it was, and say why. Was: the
  # 16 KB file became a 64 KiB torso, exit 1.
  make_particles(old.sphp 1000)
  file(MAKE_DIRECTORY ${WORK_DIR}/small)
  execute_process(COMMAND mount -t tmpfs -o size=64k sphray-test ${WORK_DIR}/small
                  RESULT_VARIABLE mounted ERROR_QUIET)
  if(NOT mounted EQUAL 0)
    message(STATUS "SKIPPED: cannot mount a tmpfs (not root?)")
    return()
  endif()
  file(COPY_FILE ${WORK_DIR}/old.sphp ${WORK_DIR}/small/old.sphp)
  execute_process(COMMAND ${MPIEXEC} ${MPIEXEC_FLAGS} -n 2 ${SPHRAY_MPI} generate random:6000
                          -o small/old.sphp
                  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE status ERROR_VARIABLE err
                  OUTPUT_QUIET TIMEOUT 50)
  file(COPY_FILE ${WORK_DIR}/small/old.sphp ${WORK_DIR}/after.sphp)
  file(GLOB left ${WORK_DIR}/small/.sphray-*)
  execute_process(COMMAND umount -l ${WORK_DIR}/small)
  expect_same_file(${WORK_DIR}/after.sphp ${WORK_DIR}/old.sphp)
  expect(1 "small/old.sphp: cannot write the output file (No space left on device)")
  if(left)
    message(FATAL_ERROR "${CASE}: temporaries left: ${left}")
  endif()
elseif(CASE STREQUAL "generate.file_size_limit")
  # The same for any user: a write past RLIMIT_FSIZE. The rank dies of SIGXFSZ (Open MPI gives
  # ranks the default disposition); the file replaced stays as it was, and the named temporary
  # is removed by the signal handler.
  make_particles(old.sphp 1000)
  file(COPY_FILE ${WORK_DIR}/old.sphp ${WORK_DIR}/reference.sphp)
  # PMIx's shared-memory files need a few MB under the same limit: 16 MB, and 17.6 MB to write.
  run(${CMAKE_COMMAND} -E env SPHRAY_TMPFILE=named prlimit --fsize=16000000 ${MPIEXEC}
      ${MPIEXEC_FLAGS} -n 1 ${SPHRAY_MPI} generate random:1100000 -o old.sphp)
  if(status EQUAL 0)
    message(FATAL_ERROR "${CASE}: a file past the limit was written")
  endif()
  expect_same_file(${WORK_DIR}/old.sphp ${WORK_DIR}/reference.sphp)
  file(GLOB left ${WORK_DIR}/.sphray-*)
  if(left)
    message(FATAL_ERROR "${CASE}: temporaries left: ${left}")
  endif()
elseif(CASE STREQUAL "generate.read_only")
  # Was: replaced without a word.
  make_particles(ro.sphp 100)
  file(CHMOD ${WORK_DIR}/ro.sphp PERMISSIONS OWNER_READ GROUP_READ WORLD_READ)
  file(COPY_FILE ${WORK_DIR}/ro.sphp ${WORK_DIR}/reference.sphp)
  run_np(2 generate random:200 -o ro.sphp)
  expect(2 "ro.sphp: the output file is read-only (use --force to replace it)")
  expect_same_file(${WORK_DIR}/ro.sphp ${WORK_DIR}/reference.sphp)
  run_np(2 generate random:200 -o ro.sphp --force)
  expect(0 "")
  file(SIZE ${WORK_DIR}/ro.sphp size)
  execute_process(COMMAND stat -c %a ${WORK_DIR}/ro.sphp OUTPUT_VARIABLE mode
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT size EQUAL 3232 OR NOT mode STREQUAL "444")
    message(FATAL_ERROR "${CASE}: --force: ${size} bytes, mode ${mode}")
  endif()
elseif(CASE STREQUAL "render.read_only")
  # Was: "use --force", which sphray-mpi did not take.
  file(WRITE ${WORK_DIR}/ro.ppm "old")
  file(CHMOD ${WORK_DIR}/ro.ppm PERMISSIONS OWNER_READ GROUP_READ WORLD_READ)
  run_np(2 render -q -s single -W 8 -H 8 -o ro.ppm)
  expect(2 "ro.ppm: the output file is read-only (use --force to replace it)")
  file(READ ${WORK_DIR}/ro.ppm text)
  if(NOT text STREQUAL "old")
    message(FATAL_ERROR "${CASE}: the read-only file changed")
  endif()
  run_np(2 render -q -s single -W 8 -H 8 -o ro.ppm --force)
  expect(0 "")
  file(READ ${WORK_DIR}/ro.ppm text)
  if(NOT text MATCHES "^P3\n8 8\n")
    message(FATAL_ERROR "${CASE}: --force did not replace the file")
  endif()
else()
  message(FATAL_ERROR "unknown CASE ${CASE}")
endif()
message(STATUS "${CASE}: ${err}")
