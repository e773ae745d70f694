// RTD_IVDEP, for the hot loops of any file (the *_simd.cpp files get it from core/simd.h).
#pragma once

/// Before a loop whose iterations carry no dependence through memory: GCC's ivdep, which also
/// spares the run-time overlap checks that GCC gives up on past ten pointer pairs (a loop
/// over eight planes is not vectorized without it). Nothing for Clang, the sanitizer build's
/// compiler, which warns of GCC's pragma as unknown and, at that build's -O1, of its own
/// equivalent as a vectorization it could not do.
#if defined(__clang__)
#define RTD_IVDEP
#else
#define RTD_IVDEP _Pragma("GCC ivdep")
#endif
