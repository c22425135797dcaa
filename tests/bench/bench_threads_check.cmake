# `retroglass bench --threads LIST` (bench/harness.cpp, issue 22): a short run of fill_flat
# at 1 and 2 threads must give a ratio at each count, in the JSON, the printed table and
# the --plot panel; a count above the machine's threads must be run and said to be
# oversubscribed; bad lists must be refused with the reason. The speed is not checked
# (a short --min-time).
#   cmake -DRETROGLASS=<exe> -DOUT=<json> -P bench_threads_check.cmake
# The files go to <json>.<random>.json(.svg), of this run alone, removed when the checks
# pass and kept when one fails.
string(RANDOM LENGTH 10 ALPHABET 0123456789abcdef run)
get_filename_component(out_dir "${OUT}" DIRECTORY)
get_filename_component(out_stem "${OUT}" NAME_WE)
set(OUT "${out_dir}/${out_stem}.${run}.json")

# ---- bad lists: refused before anything runs, naming the entry ---------------------------
foreach(case "0|0 is out of range" "a,b|'a' is not a thread count"
             "2,,3|empty entry at position 2" "2,4,2|2 is listed twice")
    string(REPLACE "|" ";" case "${case}")
    list(GET case 0 list)
    list(GET case 1 why)
    execute_process(COMMAND ${RETROGLASS} bench --threads ${list} --filter "^fill_flat/"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc EQUAL 0 OR NOT "${err}" MATCHES "${why}")
        message(FATAL_ERROR "--threads '${list}': expected a refusal saying '${why}', got "
                            "exit ${rc}:\n${out}\n${err}")
    endif()
    if("${out}" MATCHES "/threads:")
        message(FATAL_ERROR "--threads '${list}' ran benchmarks before refusing:\n${out}")
    endif()
endforeach()

# ---- 1 and 2 threads: a ratio at each --------------------------------------------------
execute_process(
    COMMAND ${RETROGLASS} bench --threads 1,2 --filter "^fill_flat/" --min-time 0.01
            --json ${OUT} --plot ${OUT}.svg
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bench --threads 1,2 exited with ${rc}:\n${out}\n${err}")
endif()
file(READ ${OUT} json)
string(JSON threads GET "${json}" threads)
string(REGEX REPLACE "[ \n]" "" threads "${threads}")
if(NOT threads STREQUAL "[1,2]")
    message(FATAL_ERROR "JSON threads ${threads}, expected [1,2]")
endif()
string(JSON nratios LENGTH "${json}" ratios)
if(NOT nratios EQUAL 2)
    message(FATAL_ERROR "expected 2 ratios (fill_flat at 1 and 2 threads), got ${nratios}:\n${out}")
endif()
file(READ ${OUT}.svg svg)
foreach(t 1 2)
    set(found 0)
    foreach(r 0 1)
        string(JSON got GET "${json}" ratios ${r} threads)
        string(JSON name GET "${json}" ratios ${r} benchmark)
        string(JSON ratio GET "${json}" ratios ${r} ratio)
        if(got EQUAL t AND name MATCHES "^fill_flat/retroglass/threads:${t}/" AND ratio GREATER 0)
            math(EXPR found "${found} + 1")
        endif()
    endforeach()
    if(NOT found EQUAL 1)
        message(FATAL_ERROR "${found} ratios of fill_flat at ${t} threads, expected 1:\n${json}")
    endif()
    foreach(side retroglass peer)
        if(NOT svg MATCHES "class=\"point\" data-side=\"${side}\" data-threads=\"${t}\" data-items-per-second=\"[0-9.e+]+\"")
            message(FATAL_ERROR "--plot: no ${side} point at ${t} threads:\n${svg}")
        endif()
    endforeach()
endforeach()
if(NOT svg MATCHES "<g class=\"panel\" data-workload=\"fill_flat\" data-peer=\"llvmpipe\">")
    message(FATAL_ERROR "--plot: no fill_flat panel:\n${svg}")
endif()
# The printed table: a row for the workload with a ratio under each count.
if(NOT out MATCHES "at threads: +1 +2\nfill_flat vs llvmpipe +[0-9]+\\.[0-9][0-9] +[0-9]+\\.[0-9][0-9]\n")
    message(FATAL_ERROR "no ratio table by thread count in the output:\n${out}")
endif()
file(REMOVE ${OUT} ${OUT}.svg)

# ---- more threads than the machine has: run, and said so -------------------------------
string(JSON hardware GET "${json}" hardware_threads)
math(EXPR over "${hardware} + 1")
execute_process(
    COMMAND ${RETROGLASS} bench --threads ${over} --filter "^fill_flat/" --min-time 0.01
            --json ${OUT}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bench --threads ${over} exited with ${rc}:\n${out}\n${err}")
endif()
file(READ ${OUT} json)
string(JSON oversubscribed GET "${json}" oversubscribed_threads 0)
if(NOT oversubscribed EQUAL over OR NOT out MATCHES "oversubscribed[^\n]*: ${over}\n"
   OR NOT out MATCHES "fill_flat/retroglass/threads:${over}/")
    message(FATAL_ERROR "--threads ${over} on ${hardware} hardware threads: not run or not "
                        "said to be oversubscribed:\n${out}\n${json}")
endif()
file(REMOVE ${OUT})
message(STATUS "ok: ratios at 1 and 2 threads, the scaling panel, ${over} threads "
               "oversubscribed, bad lists refused")
