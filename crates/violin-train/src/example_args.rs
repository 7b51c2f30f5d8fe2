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
