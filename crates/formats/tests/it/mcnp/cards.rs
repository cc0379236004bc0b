//! The card layer: title, blocks, comments, continuations, tabs, case,
//! shorthand, the column limits and `READ` cards.

use super::*;

#[test]
fn comments_continuations_tabs_and_case() {
    let text = "title card: c is no comment here $ nor this\n\
        c a comment card\n\
        \x20 C another, its c in column 3\n\
        c\n\
        1 1 -2.7 -1 &\n\
        2 $ first cell\n\
        c a comment between a card's lines\n\
        \x20    -3 IMP:N=1\n\
        2 0 1:-2:3 imp:n=0 $ the outside\n\
        \n\
        1 SO 5\n\
        2\tpx\t-1\n\
        3 Px 4\n\
        \t$ a tab continues the card above, this line has only a comment\n\
        \n\
        M1 13027.80C 1\n";
    let l = load(text);
    assert_eq!(l.scene.title, "title card: c is no comment here $ nor this");
    assert_eq!(expression(&l, "1"), "+1 -2 +3");
    assert_eq!(expression(&l, "2"), "-1 | +2 | -3");
    assert_eq!(l.scene.regions[0].description, "first cell");
    assert_eq!(l.scene.regions[1].description, "the outside");
    assert!(l.scene.regions[1].outside);
    assert_close(&body(&l, "2").params, &[-1.0]);
    assert_eq!(l.scene.materials[0].components[0].zam, (13, 27, 0));
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
}

#[test]
fn five_blanks_continue_and_a_tab_counts_as_eight() {
    let l = load(&deck(
        "1 0 -1\n     2\n\t-3\n2 0 1",
        "1 so 5\n2 px -4\n3 px 4",
        "",
    ));
    assert_eq!(expression(&l, "1"), "+1 -2 +3");
}

#[test]
fn shorthand_expands_in_surface_and_data_cards() {
    let l = load(&deck(
        "1 0 -1 -2 -3 -4 -5\n2 0 1:2:3:4:5",
        "1 s 0 2R 3\n2 p 1 1I 3 4\n3 pz 1.0+1\n4 sz 2 1.5d1\n5 s 1 2 3m 1",
        "imp:n 1 0",
    ));
    assert_close(&body(&l, "1").params, &[0.0, 0.0, 0.0, 3.0]);
    assert_close(&body(&l, "2").params, &[1.0, 2.0, 3.0, 4.0]);
    assert_close(&body(&l, "3").params, &[10.0]);
    assert_close(&body(&l, "4").params, &[0.0, 0.0, 2.0, 15.0]);
    assert_close(&body(&l, "5").params, &[1.0, 2.0, 6.0, 1.0]);
    let e = errors(&deck("1 0 -1\n2 0 1", "1 rpp -1 1 2j 1 1", ""));
    assert_eq!(
        e,
        vec![(
            5,
            12,
            "a surface takes no `J`: every value must be given".to_string()
        )]
    );
    assert_eq!(
        errors(&deck("1 0 -1\n2 0 1", "1 so 2i", ""))[0].2,
        "`2i` needs a number before it"
    );
}

#[test]
fn columns_past_128_are_ignored_and_past_80_noted() {
    let long = format!("1 0 -1{}2", " ".repeat(122));
    assert_eq!(long.chars().count(), 129);
    let l = load(&deck(&format!("{long}\n2 0 1"), "1 so 1\n2 so 2", ""));
    assert_eq!(expression(&l, "1"), "+1");
    assert_eq!(l.warnings.len(), 1);
    let w = &l.warnings[0];
    assert_eq!(w.line_col(), (2, 129));
    assert!(w.message.contains("columns past 128"), "{}", w.message);
    // Data past column 80 is read, and noted; a long comment is neither.
    let wide = format!("1 0 -1{}-2", " ".repeat(80));
    let comment = format!("2 0 1:2 ${}", "x".repeat(200));
    let l = load(&deck(&format!("{wide}\n{comment}"), "1 so 1\n2 so 2", ""));
    assert_eq!(expression(&l, "1"), "+1 +2");
    assert!(l.warnings.is_empty());
    assert!(
        l.scene
            .notes
            .iter()
            .any(|n| n.starts_with("1 line holds data past column 80")),
        "{:?}",
        l.scene.notes
    );
}

#[test]
fn message_block_title_and_text_after_the_data_block() {
    let text = "MESSAGE: outp=x.o\n  runtpe=x.r\n\nthe title\n1 0 -1\n2 0 1\n\n1 so 1\n\nm1 1001 1\n\nanything at all ( : #\n";
    let l = load(text);
    assert_eq!(l.scene.title, "the title");
    assert_eq!(l.scene.geometry.regions.len(), 2);
    assert_eq!(l.scene.materials.len(), 1);
}

#[test]
fn read_cards_bring_in_files_in_place() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cells.i"), "c the cells\n1 0 -1\n").unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/surf.i"), "1 so 3\n").unwrap();
    let main = "title\nread file=cells.i noecho\n2 0 1\n\nREAD FILE = sub/surf.i\n\n";
    let path = dir.path().join("main.i");
    let l = read_named(&path.display().to_string(), main).unwrap();
    assert_eq!(expression(&l, "1"), "+1");
    assert_eq!(expression(&l, "2"), "-1");
    assert_close(&body(&l, "1").params, &[0.0, 0.0, 0.0, 3.0]);
    // A missing file, and a file that reads itself, are located errors.
    let e = read_named(
        &path.display().to_string(),
        "t\nread file=nowhere.i\n1 0 -1\n\n1 so 1\n",
    )
    .unwrap_err();
    assert_eq!(e.items[0].line_col(), (2, 11));
    std::fs::write(dir.path().join("loop.i"), "read file=loop.i\n").unwrap();
    let e = read_named(
        &path.display().to_string(),
        "t\nread file=loop.i\n1 0 -1\n\n1 so 1\n",
    )
    .unwrap_err();
    assert!(
        e.items[0].message.contains("reads itself"),
        "{}",
        e.items[0].message
    );
    assert!(e.items[0].source.name.ends_with("loop.i"));
}

#[test]
fn a_continuation_needs_a_card_before_it() {
    let e = errors("t\n      1 0 -1\n\n1 so 1\n");
    assert_eq!(
        e,
        vec![(
            2,
            7,
            "a continuation line with no card before it".to_string()
        )]
    );
}

#[test]
fn detection_tells_mcnp_from_fluka_by_content() {
    use std::path::Path;
    use sv_formats::Format;
    let mcnp = deck("1 0 -1\n2 0 1", "1 so 1", "");
    let fluka = "TITLE\nx\nGEOBEGIN                                                              COMBNAME\n";
    assert_eq!(Format::detect(Path::new("a.inp"), &mcnp), Format::Mcnp);
    assert_eq!(Format::detect(Path::new("a.inp"), fluka), Format::Fluka);
    assert_eq!(Format::detect(Path::new("a.i"), &mcnp), Format::Mcnp);
    assert_eq!(Format::detect(Path::new("x/input"), &mcnp), Format::Mcnp);
    assert_eq!(
        Format::detect(Path::new("a.mcnp"), "anything"),
        Format::Mcnp
    );
    assert_eq!(Format::detect(Path::new("model"), &mcnp), Format::Mcnp);
    assert_eq!(
        Format::detect(Path::new("a.inp"), "no geometry here\n"),
        Format::Fluka
    );
    assert!(mcnp::looks_like(
        "Light water\n1 1 -1.0 -1 imp:n=1\n2 0 1 imp:n=0\n\n1 cz 1\n"
    ));
    assert!(!mcnp::looks_like("title\n  12   7\n  1 SPH 0 0 0 1\n"));
}
