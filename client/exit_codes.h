// Exit codes of the `ispq` command line, stable for scripts (also listed in README.md).
#ifndef ISPQ_CLIENT_EXIT_CODES_H_
#define ISPQ_CLIENT_EXIT_CODES_H_

namespace ispq::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;          // bad command line
inline constexpr int kExitInvalidInput = 3;   // unreadable file or a mesh that fails validation
inline constexpr int kExitInvalidResult = 4;  // a quantization that is not valid
inline constexpr int kExitFailed = 5;         // anything else (solver, I/O, server errors)

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_EXIT_CODES_H_
