//! `bearing-sim token NAME`: make an API token. The token goes to the client; the
//! service keeps only the `name:sha256` line printed for its tokens file.

use super::result::CliResult;
use crate::config::hash_token;

#[derive(clap::Args, Debug)]
pub struct TokenArgs {
    /// The token's name: the tenant that owns what it creates (letters, digits, -, _, .).
    pub name: String,
}

pub fn main(args: TokenArgs) -> CliResult {
    // two v4 UUIDs: 244 bits from the operating system's random source
    let token = format!(
        "bs_{}{}",
        uuid::Uuid::new_v4().simple(),
        uuid::Uuid::new_v4().simple()
    );
    let line = format!("{}:{}", args.name, hash_token(&token));
    // check the name as the service will
    crate::config::Tokens::parse(&line, "the new entry")?;
    println!("token (give it to the client; it is not stored anywhere): {token}");
    println!("line for --tokens-file: {line}");
    Ok(())
}
