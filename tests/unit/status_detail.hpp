// Shared check for the tests/unit/test_status_detail_<header>.cpp files: a non-Ok result names the
// offending input in its `detail` ("field: what is wrong"); an Ok result has detail == nullptr.
#pragma once

#include <doctest/doctest.h>

#include <cstring>
#include <string>

// r: a result struct; st: the expected Status; field: the input's name the detail must contain.
#define SK_CHECK_DETAIL(r, st, field)                                                      \
    do {                                                                                   \
        const auto& sk_r_ = (r);                                                           \
        CHECK(sk_r_.status == (st));                                                       \
        REQUIRE(sk_r_.detail != nullptr);                                                  \
        INFO("detail: " << std::string(sk_r_.detail));                                     \
        CHECK(std::strstr(sk_r_.detail, field) != nullptr);                                \
    } while (0)

// An Ok result carries no detail.
#define SK_CHECK_OK_NO_DETAIL(r)                                                           \
    do {                                                                                   \
        const auto& sk_r_ = (r);                                                           \
        CHECK(sk_r_.status == shadowkit::Status::Ok);                                      \
        CHECK(sk_r_.detail == nullptr);                                                    \
    } while (0)
