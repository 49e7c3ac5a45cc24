// Whether this test binary runs under AddressSanitizer or ThreadSanitizer, whose quarantine and
// shadow memory grow with every allocation: memory bounds are not checked there.
#pragma once

namespace lixel::testing {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

}  // namespace lixel::testing
