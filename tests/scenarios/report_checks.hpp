// Reading the reports back as the programs that consume them do: junit.xml through libxml2, validated
// against the JUnit schema CI systems read (tests/data/junit.xsd), and report.html's plot data as the
// page's script reads it.
#pragma once

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/xmlschemas.h>
#include <libxml/xpath.h>
#include <nlohmann/json.hpp>

namespace beadtwin::testing {

// libxml2's errors, collected for the failure message instead of printed.
inline void collect_xml_error(void* into, xmlErrorPtr error) {
  if (error && error->message)
    static_cast<std::string*>(into)->append(std::to_string(error->line) + ": " + error->message);
}

using XmlDoc = std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)>;

// Parses `path` and validates it against tests/data/junit.xsd; a null document (with a test failure) when
// either fails.
inline XmlDoc read_junit(const std::filesystem::path& path) {
  std::string errors;
  xmlSetStructuredErrorFunc(&errors, &collect_xml_error);
  XmlDoc doc(xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET), &xmlFreeDoc);
  const std::string xsd = std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/junit.xsd";
  std::unique_ptr<xmlSchemaParserCtxt, decltype(&xmlSchemaFreeParserCtxt)> parser(
      xmlSchemaNewParserCtxt(xsd.c_str()), &xmlSchemaFreeParserCtxt);
  xmlSchemaSetParserStructuredErrors(parser.get(), &collect_xml_error, &errors);
  std::unique_ptr<xmlSchema, decltype(&xmlSchemaFree)> schema(xmlSchemaParse(parser.get()), &xmlSchemaFree);
  bool valid = false;
  if (doc && schema) {
    std::unique_ptr<xmlSchemaValidCtxt, decltype(&xmlSchemaFreeValidCtxt)> check(
        xmlSchemaNewValidCtxt(schema.get()), &xmlSchemaFreeValidCtxt);
    xmlSchemaSetValidStructuredErrors(check.get(), &collect_xml_error, &errors);
    valid = xmlSchemaValidateDoc(check.get(), doc.get()) == 0;
  }
  xmlSetStructuredErrorFunc(nullptr, nullptr);
  EXPECT_TRUE(doc) << path << " is not XML: " << errors;
  EXPECT_TRUE(schema) << xsd << ": " << errors;
  EXPECT_TRUE(valid) << path << " is not valid JUnit XML: " << errors;
  return valid ? std::move(doc) : XmlDoc(nullptr, &xmlFreeDoc);
}

// The number an XPath expression comes to in `doc` (count(...), sum(...), an attribute as a number).
inline double xpath_number(xmlDoc* doc, const std::string& expr) {
  std::unique_ptr<xmlXPathContext, decltype(&xmlXPathFreeContext)> ctx(xmlXPathNewContext(doc),
                                                                       &xmlXPathFreeContext);
  std::unique_ptr<xmlXPathObject, decltype(&xmlXPathFreeObject)> r(
      xmlXPathEvalExpression(reinterpret_cast<const xmlChar*>(expr.c_str()), ctx.get()), &xmlXPathFreeObject);
  return r ? xmlXPathCastToNumber(r.get()) : std::nan("");
}

// The string an XPath expression comes to in `doc`.
inline std::string xpath_string(xmlDoc* doc, const std::string& expr) {
  std::unique_ptr<xmlXPathContext, decltype(&xmlXPathFreeContext)> ctx(xmlXPathNewContext(doc),
                                                                       &xmlXPathFreeContext);
  std::unique_ptr<xmlXPathObject, decltype(&xmlXPathFreeObject)> r(
      xmlXPathEvalExpression(reinterpret_cast<const xmlChar*>(expr.c_str()), ctx.get()), &xmlXPathFreeObject);
  if (!r) return {};
  xmlChar* s = xmlXPathCastToString(r.get());
  std::string text = s ? reinterpret_cast<const char*>(s) : "";
  xmlFree(s);
  return text;
}

// The plots of report.html: the JSON of each <script type="application/json" class="beadtwin-plot">, in
// page order.
inline std::vector<nlohmann::json> report_plots(const std::string& html) {
  static const std::string open = "<script type=\"application/json\" class=\"beadtwin-plot\">";
  std::vector<nlohmann::json> plots;
  for (std::size_t at = html.find(open); at != std::string::npos; at = html.find(open, at)) {
    at += open.size();
    const std::size_t end = html.find("</script>", at);
    if (end == std::string::npos) break;
    plots.push_back(nlohmann::json::parse(html.substr(at, end - at)));
    at = end;
  }
  return plots;
}

}  // namespace beadtwin::testing
