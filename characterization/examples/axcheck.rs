//! Prints the diagnostics of one AXCFIL (development aid): `cargo run --example axcheck FILE`.
fn main() {
    let path = std::env::args().nth(1).unwrap_or_default();
    let bytes = std::fs::read(&path).unwrap_or_default();
    let (f, mut d) = characterization::reader::read(&path, &bytes);
    let (_, d2) = characterization::axcfil::validate(&f);
    d.extend(d2);
    for d in &d {
        println!("{d}  // {}", d.hint);
    }
}
