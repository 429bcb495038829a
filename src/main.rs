fn main() {
    println!("vito {}", env!("CARGO_PKG_VERSION"));
}
