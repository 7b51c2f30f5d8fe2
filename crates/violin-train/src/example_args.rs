//! The `--name VALUE` options of this crate's examples, read one way.

/// The value after `--name` in `args`: `Ok(None)` when the flag is absent, an error naming the
/// flag when nothing follows it.
///
/// ```
/// let args: Vec<String> = ["corpus", "--seed", "7", "--write"].map(String::from).into();
/// assert_eq!(violin_train::example_args::flag_value(&args, "--seed"), Ok(Some("7")));
/// assert_eq!(violin_train::example_args::flag_value(&args, "--lr"), Ok(None));
/// assert!(violin_train::example_args::flag_value(&args, "--write").is_err());
/// ```
pub fn flag_value<'a>(args: &'a [String], name: &str) -> Result<Option<&'a str>, String> {
    match args.iter().position(|a| a == name) {
        None => Ok(None),
        Some(i) => match args.get(i + 1) {
            Some(v) if !v.starts_with("--") => Ok(Some(v.as_str())),
            _ => Err(format!("{name} needs a value")),
        },
    }
}

/// The values after every `--name` in `args`, in order (for options that may be repeated);
/// an error naming the flag when one has nothing after it.
///
/// ```
/// let args: Vec<String> = ["c", "--extra", "a", "--extra", "b"].map(String::from).into();
/// assert_eq!(violin_train::example_args::flag_values(&args, "--extra"), Ok(vec!["a", "b"]));
/// assert_eq!(violin_train::example_args::flag_values(&args, "--lr"), Ok(vec![]));
/// ```
pub fn flag_values<'a>(args: &'a [String], name: &str) -> Result<Vec<&'a str>, String> {
    args.iter()
        .enumerate()
        .filter(|(_, a)| *a == name)
        .map(|(i, _)| match args.get(i + 1) {
            Some(v) if !v.starts_with("--") => Ok(v.as_str()),
            _ => Err(format!("{name} needs a value")),
        })
        .collect()
}
