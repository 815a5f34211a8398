"""Learning the commonsense tables: corpora, verb folding, noun matching, counts, evaluation, rebuild."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.build import build, default_corpora, read_corpora
from wecook_core.knowledge.corpus import Corpus, Record, merge, read_csv, read_epic
from wecook_core.knowledge.evaluation import Example, evaluate, object_oracle, predict, score, split
from wecook_core.knowledge.learning import INSTRUMENTS, fold, from_examples, learn
from wecook_core.knowledge.nouns import epic_name, match, normalise, singular
from wecook_core.knowledge.recognize import load_knowledge, rank
from wecook_core.knowledge.synonyms import RECOGNISED, VerbFolder, load_synonyms
from wecook_core.resources import ASSETS_DIR

CSV = """action,objects
chop,knife;tomato
cut,knife;onion;chopping board
slice,Knife;tomatoes
stir,spoon;pot
whisk,whisk;egg
pour,oil;pan
transfer,spoon;bowl
take,knife
"""


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


# ------------------------------------------------------------------------------------------------ nouns


@pytest.mark.parametrize(("label", "name"), [
    ("Rolling-Pin", "rolling_pin"),
    ("chopping board", "chopping_board"),
    ("bowl_2", "bowl"),
    ("cup_1_3", "cup"),
    ("chef's knife", "chefs_knife"),
    ("  Olive  Oil ", "olive_oil"),
    ("7", "7"),
])
def test_normalise(label: str, name: str) -> None:
    assert normalise(label) == name


def test_epic_names_put_modifiers_first() -> None:
    assert epic_name("board:chopping") == "chopping_board"
    assert epic_name("pan:dust") == "dust_pan"
    assert epic_name("onion") == "onion"


@pytest.mark.parametrize(("word", "one"), [("tomatoes", "tomato"), ("berries", "berry"), ("dishes", "dish"),
                                           ("knives", "knif"), ("glass", "glass"), ("hummus", "hummus"),
                                           ("eggs", "egg")])
def test_singular(word: str, one: str) -> None:
    assert singular(word) == one


def test_match_tries_full_label_then_tails_with_number_variants() -> None:
    names = {"knife": "K", "olive": "O", "olive_oil": "OO", "tongs": "T", "bowl": "B"}
    assert match("Knives", names) == "K"
    assert match("olives", names) == "O"
    assert match("olive oil", names) == "OO"  # the full label before its head noun
    assert match("extra virgin olive oil", names) == "OO"
    assert match("tong", names) == "T"
    assert match("big_red_bowl_2", names) == "B"
    assert match("bowl of soup", names) is None  # the head noun is the last word
    assert match("", names) is None


# ------------------------------------------------------------------------------------------------ verbs


def test_shipped_synonyms_fold_corpus_verbs() -> None:
    folder = load_synonyms().with_classes({"chop": "cut", "make": "cut", "beat": "mix", "scatter": "sprinkle",
                                           "cover": "wrap", "roll-out": "unroll", "smear": "apply"})
    expected = {"chop": "cut", "chop-into": "cut", "slice": "cut", "dice": "cut", "make": None,
                "mix": "stir", "whisk": "stir", "beat": "stir", "scatter": "sprinkle", "season": "sprinkle",
                "roll-out": "roll", "roll-up": None, "roll-in": "dip", "roll-into": "roll", "dredge": "sprinkle",
                "dust": "sprinkle", "immerse": "dip", "pare": "peel",
                "smear": "spread", "cover": None, "dip": "dip",
                "squeeze": "squeeze", "take": None, "transfer": "transfer", "spoon-into": "transfer",
                "scoop": "transfer", "skim-off": None, "wash": None}
    assert {verb: folder.fold(verb) for verb in expected} == expected


def test_class_rules_apply_to_verbs_only_the_corpus_knows() -> None:
    folder = VerbFolder(words={"chop": "cut"}, classes={"cut": "cut", "mix": "stir"},
                        verb_classes={"julienne": "cut", "fold-in": "mix", "pick": "take"})
    assert folder.fold("julienne") == "cut"
    assert folder.fold("fold-in") == "stir"
    assert folder.fold("pick") is None
    assert folder.fold("chop-up") == "cut"


def test_synonym_targets_must_be_recognised_verbs(tmp_path: Path) -> None:
    path = write(tmp_path / "syn.yaml", "words:\n  chop: dice\n")
    with pytest.raises(InputError, match="dice") as error:
        load_synonyms(path)
    assert "words.chop" in str(error.value)
    assert RECOGNISED[-1] == "transfer" and len(RECOGNISED) == 11  # every verb of the grammar is ranked


# ---------------------------------------------------------------------------------------------- corpora


def test_csv_corpus_and_learned_counts(tmp_path: Path) -> None:
    corpus = read_csv(write(tmp_path / "c.csv", CSV))
    assert corpus.records[2] == Record("slice", ("knife", "tomatoes"), "c.csv:4", source="c")
    examples, vocabulary = fold(corpus)
    assert [e.action for e in examples] == ["cut", "cut", "cut", "stir", "stir", "pour", "transfer"]
    # objects first seen in kept records; "tomatoes" is matched to "tomato"; "take" is dropped
    assert vocabulary == ("knife", "tomato", "onion", "chopping_board", "spoon", "pot", "whisk", "egg", "oil", "pan",
                          "bowl")
    knowledge = learn(corpus, alpha=1.0)
    cut = knowledge.verbs.index("cut")
    assert knowledge.action_counts.tolist() == [3, 0, 2, 1, 0, 0, 0, 0, 0, 0, 1]
    assert knowledge.pair_counts[cut].tolist() == [3, 2, 1, 1, 0, 0, 0, 0, 0, 0, 0]
    assert knowledge.prior()["cut"] == pytest.approx((3 + 1) / (7 + 11))
    assert knowledge.likelihood("knife", "cut") == pytest.approx((3 + 1) / (7 + 11))
    assert knowledge.likelihood("egg", "stir") == pytest.approx((1 + 1) / (4 + 11))
    assert rank(knowledge, ["knife", "tomato"])[0][0] == "cut"
    assert rank(knowledge, ["whisk", "egg"])[0][0] == "stir"
    assert rank(knowledge, ["spoon"])[0][0] == "stir"  # the corpus prior: stir 2 records, transfer 1
    uniform = learn(corpus, alpha=1.0, prior="uniform")
    assert uniform.prior()["cut"] == pytest.approx(1 / 11)
    assert uniform.pair_counts.tolist() == knowledge.pair_counts.tolist()
    assert rank(uniform, ["spoon"])[0][0] == "transfer"  # spoon: 1 of transfer's 2 objects, 1 of stir's 4


def test_a_group_counts_a_verb_with_an_object_once(tmp_path: Path) -> None:
    """Burstiness: one recipe (or video) repeating "roll egg" does not make egg the object of roll."""
    text = "action,objects,group\nroll,egg,a\nroll,egg,a\nroll,egg;bowl,a\nroll,dough,b\nroll,dough,c\n"
    corpus = read_csv(write(tmp_path / "c.csv", text))
    roll = RECOGNISED.index("roll")
    per_group, per_record = learn(corpus), learn(corpus, per_group=False)
    objects = per_group.objects
    assert dict(zip(objects, per_group.pair_counts[roll].tolist(), strict=True)) == {"egg": 1, "bowl": 1, "dough": 2}
    assert dict(zip(objects, per_record.pair_counts[roll].tolist(), strict=True)) == {"egg": 3, "bowl": 1,
                                                                                       "dough": 2}
    assert per_group.action_counts[roll] == 3 and per_record.action_counts[roll] == 5
    assert per_group.likelihood("dough", "roll") > per_group.likelihood("egg", "roll")
    assert per_record.likelihood("dough", "roll") < per_record.likelihood("egg", "roll")


def test_a_verb_named_after_its_tool_is_done_with_it(tmp_path: Path) -> None:
    corpus = read_csv(write(tmp_path / "c.csv", "action,objects\nwhisk,egg\nwhisk-in,sugar\nbeat,egg\nwhisk,\n"))
    examples, _ = fold(corpus)
    assert [(e.action, e.objects) for e in examples] == [
        ("stir", ("egg", "whisk")), ("stir", ("sugar", "whisk")), ("stir", ("egg",)), ("stir", ("whisk",))]
    assert INSTRUMENTS["whisk"] == "whisk"


def test_records_without_objects_are_not_learned(tmp_path: Path) -> None:
    corpus = read_csv(write(tmp_path / "c.csv", "action,objects\ncut,knife\ncut,\nstir,  ;\n"))
    examples, _ = fold(corpus)
    assert [e.action for e in examples] == ["cut"]


def test_csv_declares_corpus_source_licence_and_context(tmp_path: Path) -> None:
    text = ("# corpus: mine\n# source: my notes, 2026\n# licence: CC0 1.0\naction,objects,group,context\n"
            "stir,pot,r1,spoon\nchop,onion,r1,\n")
    corpus = read_csv(write(tmp_path / "c.csv", text))
    assert corpus.records[0] == Record("stir", ("pot",), "r1", ("spoon",), "mine")
    assert corpus.records[1].context == () and corpus.records[1].source == "mine"
    assert corpus.licences == ("CC0 1.0",)
    assert corpus.sources == ("c.csv (2 records, CSV: my notes, 2026)",)
    assert fold(corpus)[0][0].objects == ("pot", "spoon")


@pytest.mark.parametrize(("text", "place"), [
    ("action,objects\ncut\n", "line 2"),
    ("cut,knife,g,ctx,extra\n", "line 1"),
    ("cut,knife\n,tomato\n", "line 2"),
    ("action,objects\n", None),
])
def test_bad_csv_names_file_and_line(tmp_path: Path, text: str, place: str | None) -> None:
    path = write(tmp_path / "bad.csv", text)
    with pytest.raises(InputError) as error:
        read_csv(path)
    assert error.value.path == str(path)
    assert error.value.place == place


def fake_epic(root: Path) -> Path:
    (root / "epic100").mkdir(parents=True)
    (root / "epic55").mkdir()
    write(root / "epic100" / "EPIC_100_noun_classes.csv",
          'id,key,instances,category\n'
          '0,knife,"[\'knife\', \'blade\']",cutlery\n'
          '1,tomato,"[\'tomato\', \'tomato:cherry\']",vegetables\n'
          '2,board:chopping,"[\'board:chopping\', \'board\']",utensils\n'
          '3,spoon,"[\'spoon\']",cutlery\n'
          '4,pot,"[\'pot\']",cookware\n')
    write(root / "epic100" / "EPIC_100_verb_classes.csv",
          'id,key,instances,category\n'
          '0,take,"[\'take\', \'pick-up\']",retrieve\n'
          '1,cut,"[\'cut\', \'chop\', \'julienne\']",split\n'
          '2,mix,"[\'mix\', \'stir\']",merge\n')
    write(root / "epic100" / "EPIC_100_validation.csv",
          "narration_id,video_id,start_timestamp,start_frame,verb,all_nouns,all_noun_classes\n"
          "V1_0,V1,00:00:00.20,10,pick-up,['spoon'],[3]\n"
          "V1_1,V1,00:00:00.40,20,stir,['pot'],[4]\n")
    write(root / "epic55" / "EPIC_train_action_labels.csv",
          "uid,video_id,start_timestamp,start_frame,verb,all_nouns,all_noun_classes\n"
          "2,P1,00:00:05.00,300,julienne,['tomato:cherry'],[9]\n"
          "0,P1,00:00:01.67,100,take,['blade'],[7]\n"
          "1,P1,00:00:03.33,200,chop,\"['tomato', 'board']\",\"[8, 9]\"\n"
          "3,P2,00:00:01.67,100,cut,['tomato'],[8]\n")
    return root


def test_epic_reader_maps_classes_aliases_and_take_context(tmp_path: Path) -> None:
    corpus = read_epic(fake_epic(tmp_path / "epic"))
    assert corpus.vocabulary == ("knife", "tomato", "chopping_board", "spoon", "pot")
    assert corpus.nouns["cherry_tomato"] == "tomato" and corpus.nouns["blade"] == "knife"
    assert corpus.noun_categories["chopping_board"] == "utensils"
    by_verb = {r.action: r for r in corpus.records}
    assert by_verb["chop"].objects == ("tomato", "chopping_board")
    assert by_verb["chop"].context == ("knife",)  # "take blade" 1.7 s before, same video: the held tool
    assert by_verb["julienne"].context == ("knife",)  # two records back, still held
    assert by_verb["cut"].context == ()  # another video
    assert by_verb["stir"].objects == ("pot",) and by_verb["stir"].context == ("spoon",)
    assert read_epic(tmp_path / "epic", held_s=0).records[0].context == ()  # no held tool, no take window
    assert read_epic(tmp_path / "epic", held_s=0, context=1).records[0].context == ()  # julienne: take is 2 back
    assert read_epic(tmp_path / "epic", held_s=0, context=2).records[0].context == ("knife",)
    per_record = learn(corpus, per_group=False)
    cut, knife = per_record.verbs.index("cut"), per_record.objects.index("knife")
    assert per_record.action_counts[cut] == 3
    assert per_record.pair_counts[cut, knife] == 2
    knowledge = learn(corpus)  # chop and julienne with a knife in one video: one video cuts with a knife
    assert knowledge.action_counts[cut] == 2
    assert knowledge.pair_counts[cut, knife] == 1
    assert rank(knowledge, ["Blade", "cherry tomatoes"])[0][0] == "cut"
    assert knowledge.aliases["board"] == "chopping_board"


def test_epic_held_tool_is_put_down_and_forgotten(tmp_path: Path) -> None:
    """A tool taken is held until put down, for at most HELD_S seconds; an ingredient taken is not a held
    tool; the other hand's take records are no tool either (the tool predicate decides)."""
    root = fake_epic(tmp_path / "epic")
    write(root / "epic55" / "EPIC_train_action_labels.csv",
          "uid,video_id,start_timestamp,start_frame,verb,all_nouns,all_noun_classes\n"
          "0,P1,00:00:00.00,0,take,['knife'],[0]\n"
          "1,P1,00:00:10.00,600,cut,['tomato'],[1]\n"
          "2,P1,00:00:12.00,720,put-down,['knife'],[0]\n"
          "3,P1,00:00:14.00,840,cut,['tomato'],[1]\n"
          "4,P1,00:00:20.00,1200,take,['knife'],[0]\n"
          "5,P1,00:00:56.00,3360,cut,['tomato'],[1]\n"
          "6,P1,00:00:57.00,3420,take,['tomato'],[1]\n"
          "7,P1,00:00:58.00,3480,chop,['board'],[2]\n")
    write(root / "epic100" / "EPIC_100_verb_classes.csv",
          'id,key,instances,category\n0,take,"[\'take\']",retrieve\n1,cut,"[\'cut\', \'chop\']",split\n'
          '2,put,"[\'put-down\']",leave\n')
    records = [r for r in read_epic(root).records if r.group == "P1"]
    assert [r.context for r in records if r.action in ("cut", "chop")] == [("knife",), (), (), ()]
    longer = [r for r in read_epic(root, held_s=40).records if r.group == "P1"]
    assert [r.context for r in longer if r.action in ("cut", "chop")] == [("knife",), (), ("knife",), ("knife",)]
    everything = [r for r in read_epic(root, is_tool=lambda name: True).records if r.group == "P1"]
    assert everything[-1].context == ("tomato",)  # the tomato taken just before, were it a tool


def test_merged_corpora_share_nouns(tmp_path: Path) -> None:
    epic = read_epic(fake_epic(tmp_path / "epic"))
    mine = read_csv(write(tmp_path / "mine.csv", "action,objects\ndip,cherry tomatoes;hummus\n"))
    corpus = merge([epic, mine])
    knowledge = learn(corpus)
    assert knowledge.objects[-1] == "hummus"  # new noun appended to EPIC's vocabulary
    dip = knowledge.verbs.index("dip")
    assert knowledge.pair_counts[dip, knowledge.objects.index("tomato")] == 1  # matched through EPIC's alias
    assert corpus.licences == ("CC BY-NC 4.0",)


def test_not_a_corpus(tmp_path: Path) -> None:
    from wecook_core.knowledge.corpus import read_corpus

    with pytest.raises(InputError, match=r"EPIC.*recipes"):
        read_corpus(tmp_path)
    with pytest.raises(InputError, match="no such"):
        read_corpus(tmp_path / "missing.csv")


# ------------------------------------------------------------------------------------------- evaluation


def test_split_is_deterministic_and_by_group() -> None:
    examples = [Example("cut", ("knife",), f"v{i % 10}") for i in range(100)]
    train, test, groups = split(examples, seed=3, fraction=0.3)
    assert groups == 3 and len(test) == 30
    assert not {e.group for e in train} & {e.group for e in test}
    assert split(examples, seed=3, fraction=0.3) == (train, test, groups)
    assert split(examples, seed=4, fraction=0.3)[1] != test


def test_score_by_hand() -> None:
    verbs = ("cut", "stir", "pour")
    metrics = score(["cut", "cut", "stir", "stir"], ["cut", "stir", "stir", "cut"], verbs)
    assert metrics.accuracy == 0.5
    assert [(s.precision, s.recall, s.support, s.predicted) for s in metrics.per_verb] == [
        (0.5, 0.5, 2, 2), (0.5, 0.5, 2, 2), (0.0, 0.0, 0, 0)]
    assert metrics.macro_precision == 0.5 and metrics.macro_recall == 0.5  # pour has no held-out records


def test_evaluate_a_corpus_where_objects_decide() -> None:
    rng = np.random.default_rng(0)
    rows = []
    for i in range(300):
        verb = ("cut", "stir", "pour")[int(rng.integers(3)) if i % 2 else 0]  # cut is the majority
        obj = {"cut": "knife", "stir": "spoon", "pour": "jug"}[verb]
        rows.append(Record(verb, (obj, "bowl"), f"video{i % 20}"))
    result = evaluate(Corpus(tuple(rows)), seed=0)
    assert result.model.accuracy == 1.0 and result.model.macro_recall == 1.0
    assert result.majority == "cut"
    test_cut = next(s for s in result.baseline.per_verb if s.verb == "cut")
    assert result.baseline.accuracy == pytest.approx(test_cut.support / result.test_records)
    assert result.baseline.macro_recall == pytest.approx(1 / 3)
    assert result.test_groups == 4
    assert result.by_source == ()  # one corpus
    assert result.ceiling is not None and result.ceiling.accuracy == 1.0


def test_the_ceiling_is_what_the_objects_of_the_held_out_records_can_tell() -> None:
    """Salt over a pot is poured in some records and stirred in others: no model names both right."""
    rows = [Record(("pour", "stir")[i % 2], ("salt", "pot"), f"video{i // 2 % 10}") for i in range(40)]
    rows += [Record("cut", ("knife", "onion"), f"video{i % 10}") for i in range(20)]
    result = evaluate(Corpus(tuple(rows)), seed=0)
    ceiling = result.ceiling
    assert ceiling is not None
    assert ceiling.accuracy == pytest.approx(0.5 * 8 / 12 + 4 / 12)  # cut always right, salt + pot half the time
    assert result.model.accuracy <= ceiling.accuracy
    assert ceiling.macro_recall == pytest.approx((1 + 1 + 0) / 3)  # one of pour and stir is never predicted


def test_the_objects_oracle_names_each_object_set_by_its_most_frequent_verb() -> None:
    """Three salt-over-pot records poured, one stirred, and a cut: the oracle names every salt + pot pour, so
    it misses only the stir, whatever model is behind the held-out figures."""
    examples = [Example("pour", ("salt", "pot"), "v1"), Example("stir", ("pot", "salt"), "v2"),
                Example("pour", ("salt", "pot"), "v3"), Example("pour", ("salt", "pot"), "v4"),
                Example("cut", ("knife", "onion"), "v5"), Example("stir", ("spoon",), "v6"),
                Example("cut", ("spoon",), "v7")]
    assert object_oracle(examples, ("cut", "stir", "pour")) == ["pour"] * 4 + ["cut", "cut", "cut"]  # tie: cut
    rows = [Record(("pour", "stir")[i % 2], ("salt", "pot"), f"video{i // 2 % 10}") for i in range(40)]
    rows += [Record("cut", ("knife", "onion"), f"video{i % 10}") for i in range(20)]
    result = evaluate(Corpus(tuple(rows)), seed=0)
    assert result.oracle is not None
    assert result.model.accuracy <= result.oracle.accuracy == pytest.approx((4 + 4) / 12)
    assert result.oracle_by_source == ()


def test_evaluation_reports_each_corpus() -> None:
    rows = [Record(verb, (obj,), f"{source}{i % 10}", source=source)
            for source in ("a", "b") for i in range(100)
            for verb, obj in ((("cut", "knife"), ("stir", "spoon"))[i % 2],)]
    rows += [Record("pour", ("spoon",), f"b{i}", source="b") for i in range(10)]  # b: spoon is also poured
    corpus = Corpus(tuple(rows))
    result = evaluate(corpus, seed=1, prior="uniform")
    by_source = dict(result.by_source)
    assert list(by_source) == ["a", "b"]
    assert sum(s.support for m in by_source.values() for s in m.per_verb) == result.test_records
    # each corpus is held out on its own: two of a's ten groups and two of b's ten
    examples, vocabulary = fold(corpus)
    train, test, held = split(examples, seed=1)
    assert held == 4 and {e.source for e in test} == {"a", "b"}
    knowledge = from_examples(train, vocabulary, corpus, prior="uniform")
    for source in ("a", "b"):
        mine = [e for e in test if e.source == source]
        assert by_source[source] == score([e.action for e in mine], predict(knowledge, mine), knowledge.verbs)
    assert by_source["b"].accuracy < 1.0  # the poured spoon and the stirred spoon cannot both be named
    ceilings = dict(result.ceiling_by_source)
    assert list(ceilings) == ["a", "b"]
    for source in ("a", "b"):
        assert [v.support for v in ceilings[source].per_verb] == [v.support for v in by_source[source].per_verb]


# --------------------------------------------------------------------------------------------- rebuild


def test_build_from_a_csv_writes_tables_and_source(tmp_path: Path) -> None:
    corpus = write(tmp_path / "c.csv", CSV)
    built = build([corpus], tmp_path / "out")
    assert [p.name for p in built.files] == ["commonsense.json", "SOURCE.md"]
    knowledge = load_knowledge(tmp_path / "out" / "commonsense.json")
    assert knowledge.action_counts.tolist() == built.knowledge.action_counts.tolist()
    assert knowledge.prior_kind == "uniform"
    assert [e.seed for e in built.evaluations] == [0, 1, 2, 3, 4]
    source = (tmp_path / "out" / "SOURCE.md").read_text()
    assert "c.csv (8 records, CSV)" in source and "CC BY-NC" not in source
    assert len(knowledge.components) == 1 and "mixture" in source  # one corpus: one component
    assert "| mixed by corpus, objects in their roles | all |" in source
    assert "| pooled, uniform, per group | all |" in source and "ceiling" in source
    pooled = build([corpus], tmp_path / "pooled", mixed=False)
    assert not pooled.knowledge.components and pooled.knowledge.alpha == 1.0
    source = (tmp_path / "pooled" / "SOURCE.md").read_text()
    assert "| uniform, per group | all |" in source and "| corpus, per group | all |" in source
    assert "| uniform, per record | all |" in source


@pytest.mark.slow
def test_shipped_tables_are_what_the_shared_corpora_teach(shared: Path) -> None:
    """The shipped counts are reproducible from the corpora read in place (same defaults as `learn`)."""
    from wecook_core.knowledge.mixture import ALPHA, learn_mixed

    shipped = json.loads((ASSETS_DIR / "knowledge" / "commonsense.json").read_text())
    knowledge = learn_mixed(read_corpora(default_corpora()))
    assert list(knowledge.verbs) == shipped["verbs"]
    assert list(knowledge.objects) == shipped["objects"]
    assert knowledge.action_counts.tolist() == shipped["action_counts"]
    assert knowledge.pair_counts.tolist() == shipped["pair_counts"]
    assert shipped["prior"] == "uniform" and shipped["alpha"] == ALPHA
    assert [c.source for c in knowledge.components] == [c["source"] for c in shipped["components"]]
    for mine, theirs in zip(knowledge.components, shipped["components"], strict=True):
        assert mine.pair_counts.tolist() == theirs["pair_counts"] and mine.totals.tolist() == theirs["totals"]
    source = (ASSETS_DIR / "knowledge" / "SOURCE.md").read_text()
    assert "CC BY-NC 4.0" in source and "public domain" in source and "recipes.csv" in source
