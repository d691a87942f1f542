# Cross builds for Cortex-M with Debian's arm-none-eabi toolchain (gcc-arm-none-eabi,
# libnewlib-arm-none-eabi, libstdc++-arm-none-eabi-newlib). The CPU comes from the cache variable
# STICKSLIP_MCU_FLAGS (the presets cortex-m4f and cortex-m0plus set it), e.g.
#   -mcpu=cortex-m0plus -mthumb -mfloat-abi=soft
# A toolchain file is where a cross build's CPU and runtime flags belong (the *_INIT variables),
# so no target of the project sets them.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_RANLIB arm-none-eabi-ranlib)
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "arm-none-eabi-size")

# Without a board's startup files the compiler checks cannot link an executable.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(STICKSLIP_MCU_FLAGS "-mcpu=cortex-m0plus -mthumb -mfloat-abi=soft" CACHE STRING
    "CPU flags of the Cortex-M target")
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES STICKSLIP_MCU_FLAGS)

# No exceptions, no RTTI, every function and object in its own section (the linker drops what
# is not called), and no thread-safe statics (bare metal, one core: no __cxa_guard_*).
set(CMAKE_C_FLAGS_INIT "${STICKSLIP_MCU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${STICKSLIP_MCU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit -Wno-psabi")
# newlib-nano, the system calls stubbed (nosys: a program that calls none links), and unused
# sections dropped.
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=nano.specs --specs=nosys.specs -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
