// The project's one HTML escape (issue 26: the line view had its own copy of the report's).
#include "hrgbench/report/html_escape.hpp"

#include <gtest/gtest.h>

namespace hrgbench::report {
namespace {

TEST(HtmlEscape, EveryCharacterThatEndsTextOrAnAttributeIsAnEntity) {
  EXPECT_EQ(HtmlEscape("a < b && c > \"d\" 'e'"),
            "a &lt; b &amp;&amp; c &gt; &quot;d&quot; &#39;e&#39;");
  EXPECT_EQ(HtmlEscape("</script><img src=x onerror=alert(1)>"),
            "&lt;&#47;script&gt;&lt;img src=x onerror=alert(1)&gt;");
}

TEST(HtmlEscape, NoUrlSurvivesAndOtherTextIsKept) {
  EXPECT_EQ(HtmlEscape("sqlite:///srv/results.sqlite"),
            "sqlite:&#47;&#47;&#47;srv&#47;results.sqlite");
  EXPECT_EQ(HtmlEscape("τ = 1000 ± 2.5 s"), "τ = 1000 ± 2.5 s");
  EXPECT_EQ(HtmlEscape(""), "");
}

}  // namespace
}  // namespace hrgbench::report
