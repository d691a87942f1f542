# Smoke test of stickslip_tradeoff (a few seconds; never checks speed):
#   MODE=run          a tiny run (1 scene, 2 dt, 2 s) -> the CSV has every column, the expected rows,
#                     no NaN/Inf, and `report` turns it into markdown and plot data
#   MODE=bad_<what>   a bad --models/--integrators/--dt/--scalars is refused: non-zero exit, a message
# cmake -DHARNESS=<stickslip_tradeoff> -DWORK_DIR=<dir> -DMODE=<mode> -P smoke_test.cmake
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY ${WORK_DIR})

set(tiny --kinds lorry --frictions coulomb --K 0.8 --damping 504 --dt 1,5 --duration 2
         --models stick-slip,signum --integrators exact,euler --scalars double,float
         --repetitions 1 --peer-repetitions 1 --min-repetition-ms 0
         --peers dopri5-events --tolerances 1e-6)

function(expect_refused option value message)
  set(args ${tiny})
  list(FIND args ${option} at)
  math(EXPR value_at "${at} + 1")
  list(REMOVE_AT args ${at} ${value_at})
  execute_process(COMMAND ${HARNESS} run ${args} ${option} ${value} --output ${WORK_DIR}/refused.csv
                  RESULT_VARIABLE status ERROR_VARIABLE stderr OUTPUT_QUIET)
  if(status EQUAL 0)
    message(FATAL_ERROR "${option} ${value} was accepted")
  endif()
  string(FIND "${stderr}" "${message}" at)
  if(at LESS 0)
    message(FATAL_ERROR "${option} ${value}: expected '${message}' on stderr, got: ${stderr}")
  endif()
  if(EXISTS ${WORK_DIR}/refused.csv)
    message(FATAL_ERROR "${option} ${value}: an output file was left behind")
  endif()
endfunction()

if(MODE STREQUAL "bad_model")
  expect_refused(--models stick-slip,coulomb "unknown model 'coulomb'")
elseif(MODE STREQUAL "bad_integrator")
  expect_refused(--integrators exact,rk45 "unknown integrator 'rk45'")
elseif(MODE STREQUAL "bad_dt")
  expect_refused(--dt 1,0.33 "whole multiple")
elseif(MODE STREQUAL "bad_scalar")
  expect_refused(--scalars half "unknown scalar type 'half'")
elseif(MODE STREQUAL "run")
  set(csv ${WORK_DIR}/smoke.csv)
  file(REMOVE ${csv})
  execute_process(COMMAND ${HARNESS} run ${tiny} --output ${csv} RESULT_VARIABLE status ERROR_VARIABLE stderr)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "run failed (${status}): ${stderr}")
  endif()
  file(STRINGS ${csv} lines)
  list(GET lines 0 header)
  set(expected "scene,kind,friction,K,b_ns_per_m,ffk_n,ffs_n,duration_s,implementation,model,integrator,\
tolerance,scalar,dt_ms,steps,status,ns_per_sample_median,ns_per_sample_min,ns_per_sample_max,repetitions,\
instructions_per_sample,t_ax,t_ax_ref,t_ax_rel_err,p,p_ref,p_abs_err,a_x_rms_err,a_x_rms_err_rel,x_r_rms_err,\
x_r_rms_err_rel,solver_t_ax_rel_err,solver_a_x_rms_err_rel,solver_x_r_rms_err_rel,events,note")
  if(NOT header STREQUAL expected)
    message(FATAL_ERROR "header\n  ${header}\nexpected\n  ${expected}")
  endif()
  # 2 models x 2 integrators x 2 scalars x 2 dt, plus the peer at 2 dt.
  list(LENGTH lines count)
  if(NOT count EQUAL 19)
    math(EXPR rows "${count} - 1")
    message(FATAL_ERROR "expected 18 rows, got ${rows}")
  endif()
  string(TOLOWER "${lines}" lower)
  if(lower MATCHES "(^|[,;])-?(nan|inf)")
    message(FATAL_ERROR "NaN or Inf in the CSV")
  endif()
  foreach(needle "stick-slip,exact,,double,1,2000,ok," "odeint-dopri5-events,1e-06,double,5,400,ok,")
    string(FIND "${lines}" "${needle}" at)
    if(at LESS 0)
      message(FATAL_ERROR "no row with '${needle}'")
    endif()
  endforeach()
  file(WRITE ${WORK_DIR}/machine.txt "cpu: test\ncores: 1\n")
  execute_process(COMMAND ${HARNESS} report --results ${csv} --results-link smoke.csv
                          --machine ${WORK_DIR}/machine.txt --output ${WORK_DIR}/smoke.md
                          --plot-dir ${WORK_DIR}/plot --image-link img --command smoke
                  RESULT_VARIABLE status ERROR_VARIABLE stderr)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "report failed (${status}): ${stderr}")
  endif()
  file(READ ${WORK_DIR}/smoke.md md)
  foreach(section "## Targets" "## Recommendation" "## Peers" "lorry-K0.8-b504")
    string(FIND "${md}" "${section}" at)
    if(at LESS 0)
      message(FATAL_ERROR "the report has no '${section}'")
    endif()
  endforeach()
  if(NOT EXISTS ${WORK_DIR}/plot/pareto.gp)
    message(FATAL_ERROR "no gnuplot script")
  endif()
else()
  message(FATAL_ERROR "unknown MODE '${MODE}'")
endif()
