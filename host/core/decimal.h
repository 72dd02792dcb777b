// Numbers as pmcr's command line takes them: decimal only. strtod and strtol alone would also
// read hexadecimal ("0x10" is 16), "inf", "nan" and leading blanks; an option's value that is
// not written in decimal is an error naming the option, not a number read some other way.
#pragma once

#include <string_view>

namespace pmcr {

// An optional sign and decimal digits: "12", "-3", "+7".
bool isDecimalInteger(std::string_view text);

// A decimal integer or fraction with an optional exponent: "12", "-0.5", ".5", "3.", "1e-3",
// "2.5E+4". Not "0x10", "inf", "nan", " 1", "1,5" nor "".
bool isDecimalNumber(std::string_view text);

}  // namespace pmcr
