// UNDER_SANITIZER: 1 when built with AddressSanitizer (GCC's or clang's
// way of saying so), else 0. Sanitizers multiply the memory a process uses
// (shadow memory, redzones, a quarantine of freed blocks), so measured
// peaks say nothing about a memory model there.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_SANITIZER 1
#endif
#endif
#ifndef UNDER_SANITIZER
#define UNDER_SANITIZER 0
#endif
