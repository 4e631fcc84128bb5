#pragma once
// The `normal_law` key of an [[interaction]] and the keys of each normal law, read, written back
// and documented from the registry (normal_laws.hpp): no list of laws or keys is kept here.
#include <optional>
#include <string>
#include <vector>

#include "common/config.hpp"
#include "common/option_doc.hpp"
#include "simulate/materials.hpp"
#include "simulate/normal_laws.hpp"

namespace shapepress::simulate {

// The registered laws' names, the first the default ("hertz", "multicontact", …).
std::vector<std::string> normal_law_names();

// The name of a law as `normal_law` states it.
std::string normal_law_name(const NormalLawChoice& law);

// Reads `normal_law` and that law's keys from an [[interaction]] table; `where` names the
// interaction in messages. `replace`, when given (plate --model), is the law used instead of the
// table's (which is still read and checked). A key of another law is an InputError naming the
// law it needs, so no key is silently unused.
NormalLawChoice read_normal_law(const ConfigTable& interaction, const std::string& where,
                                const std::optional<std::string>& replace = std::nullopt);

// `normal_law = "<name>"` and every parameter of the law, one `key = value` line each, as
// read_normal_law reads them back to the same values.
std::string normal_law_toml(const NormalLawChoice& law);

// The config reference rows: `normal_law`, then every law's keys.
std::vector<OptionDoc> normal_law_options();

// One line for reports: the law of a pair with its constants ("hertz", "multicontact (Eq. 6),
// lambda_p = 0.3, …").
std::string describe_normal_law(const PairConstants& pair);

}  // namespace shapepress::simulate
