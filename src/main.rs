fn main() {
    println!("faze4: command line not built yet");
}
