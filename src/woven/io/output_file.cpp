#include "woven/io/output_file.hpp"

#include "woven/common/error.hpp"
#include "woven/io/input_file.hpp"

namespace woven::io {

int json_depth(std::string_view text, int stop)
{
    int depth = 0, deepest = 0;
    bool in_string = false;
    for (std::size_t k = 0; k < text.size(); ++k) {
        const char c = text[k];
        if (in_string) {
            if (c == '\\')
                ++k;
            else if (c == '"')
                in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest && (deepest = depth) > stop) return deepest;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

nlohmann::json parse_output_json(std::string_view text, const std::string& source, const std::string& expected, int max_depth)
{
    if (json_depth(text, max_depth) > max_depth)
        throw InputError(source, "json", "expected " + expected + " nested at most " + std::to_string(max_depth) + " deep");
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(source, "json", "expected " + expected + " (not JSON: syntax error at byte " + std::to_string(e.byte) + ")");
    } catch (const nlohmann::json::exception&) {  // out_of_range: a number beyond double's range
        throw InputError(source, "json", "expected " + expected + " (a number out of range)");
    }
}

nlohmann::json read_output_json(const std::string& path, std::size_t limit, const std::string& expected)
{
    return parse_output_json(read_input_file(path, limit, {"file", expected}), path, expected);
}

std::string read_output_member(const std::string& path, std::size_t limit)
{
    return read_input_file(path, limit, {"file", "a file of the output set"});
}

}  // namespace woven::io
