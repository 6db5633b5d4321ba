"""Copy measured agent results into the README and its two result pages, docs/results.md and
docs/interrogator.md (run from the repository root after the commands below), so that their tables are
generated, never typed:

    cof-gym evaluate --out out/evaluate                                              # v2 default suite
    cof-gym evaluate --suite experiments/suites/v2_no_systematic_errors.json --episodes 60 --out out/evaluate-v2-no-errors
    cof-gym evaluate --suite experiments/suites/v2_stress_tables_grid.json --out out/evaluate-v2-stress-tables
    cof-gym evaluate --suite experiments/suites/v2_extremes_grid.json --out out/evaluate-v2-extremes
    cof-gym evaluate --suite experiments/suites/v2_heldout_grid.json --out out/evaluate-v2-heldout
    cof-gym evaluate --suite experiments/suites/v2_heldout2_grid.json --out out/evaluate-v2-heldout2
    cof-gym evaluate --suite experiments/suites/v2_heldout3_grid.json --out out/evaluate-v2-heldout3
    cof-gym evaluate --suite experiments/suites/v2_heldout4_grid.json --out out/evaluate-v2-heldout4
    cof-gym evaluate --suite experiments/suites/v2_heldout5_grid.json --out out/evaluate-v2-heldout5
    cof-gym evaluate --suite experiments/suites/v2_heldout6_grid.json --out out/evaluate-v2-heldout6
    cof-gym evaluate --suite experiments/suites/v2_heldout7_grid.json --out out/evaluate-v2-heldout7
    cof-gym evaluate --env-kwargs encoder_lag_s:0.01 --out out/evaluate-v2-encoder-lag --agents \
        oracle,staircase-paper,staircase,phase-rule,phase-rule-ar1,model-based,robust-model,robust-model-ar1,interrogator
    cof-gym evaluate --agents phase-rule,phase-rule-ar1,robust-model,robust-model-ar1 --out out/evaluate-ar1
    cof-gym evaluate --env-kwargs track_irregularity:ore_low --out out/evaluate-v2-track-ore-low
    cof-gym evaluate --env-kwargs track_irregularity:ore_high --out out/evaluate-v2-track-ore-high
    cof-gym evaluate --env-kwargs encoder_pulses_per_rev:100 --out out/evaluate-v2-encoder-pulses
    cof-gym evaluate --env-kwargs encoder_pulses_per_rev:100 encoder_runout:0.0005 --out out/evaluate-v2-encoder-runout
    cof-gym evaluate --env-kwargs encoder_pulses_per_rev:100 encoder_runout:0.0005 lock_in:rotation \
        --out out/evaluate-v2-encoder-runout-rotation
    cof-gym evaluate --env-kwargs lock_in:rotation --out out/evaluate-v2-lock-in-rotation
    cof-gym evaluate --agents phase-rule,phase-rule-rotation,interrogator,interrogator-rotation --paired interrogator \
        --out out/evaluate-v2-rotation-clear
    cof-gym evaluate --agents phase-rule,phase-rule-rotation,interrogator,interrogator-rotation --paired interrogator \
        --env-kwargs encoder_pulses_per_rev:100 encoder_runout:0.0005 lock_in:rotation \
        --out out/evaluate-v2-rotation-clear-runout
    cof-gym evaluate --suite in-service                              # task v3 (its default --out)
    cof-gym evaluate --suite in-service --agents phase-rule-in-service,phase-rule-ar1,phase-rule-gated,\
robust-model-ar1,robust-model-gated,model-based-zeroed-knee-ar1,phase-rule-rotation,interrogator-rotation \
        --out out/evaluate-in-service-variants
    python experiments/select_phase_rule.py --in-service --markdown out/select_phase_rule_in_service.md
    python experiments/select_phase_rule.py --in-service --corrected-se \
        --markdown out/select_phase_rule_in_service_ar1.md
    cof-gym evaluate --suite in-service --env-kwargs track_irregularity:smooth --out out/evaluate-in-service-smooth
    cof-gym evaluate --suite experiments/suites/v2_heldout_grid.json --env CofGym/TorqueInterrogationInService-v3 \
        --out out/evaluate-in-service-heldout
    python experiments/track_lag_spread.py --out out/track_lag_spread.md   # the lag's spread on v3's tracks
    python experiments/train_interrogator.py --env CofGym/TorqueInterrogationInService-v3 \
        --out runs/interrogator_in_service --fit-only                   # the learned interrogator on task v3
    python experiments/train_interrogator.py --env CofGym/TorqueInterrogationInService-v3 \
        --out runs/interrogator_in_service --reuse --grid floor_until   # ... its selection and report
    cp -r runs/interrogator_in_service/ensemble runs/interrogator-v3           # rule 144's candidate A
    python experiments/train_estimator.py --env CofGym/TorqueInterrogationInService-v3 \
        --policy runs/interrogator_in_service/ensemble --set ceiling_stop=false --out runs/estimator_env_v3 \
        --climbs env=8000 --collect-only                                # candidate B: A's own climbs, then
    python experiments/train_interrogator.py --env CofGym/TorqueInterrogationInService-v3 \
        --out runs/interrogator_in_service_guarded --reuse --grid floor_until --probing-guard \
        --add-guard-climbs runs/estimator_env_v3/onpolicy_env_DIGEST_v3.npz  # A's networks copied in first
    cp -r runs/interrogator_in_service_guarded/ensemble runs/interrogator-v3-guarded
    cof-gym evaluate --suite experiments/suites/GRID.json --env CofGym/TorqueInterrogationInService-v3 \
        --env-kwargs counter_torque:CT --agents interrogator,interrogator:runs/interrogator-v3 \
        --out out/rule144-A-GRID-ctCT       # GRID: v2_validation_grid, v2_validation_procedural_grid; CT: False, True
    cof-gym evaluate (the same) --agents interrogator:runs/interrogator-v3-guarded --out out/rule144-B-GRID-ctCT
    cof-gym evaluate --suite in-service --agents interrogator-in-service,interrogator,phase-rule-in-service,\
staircase-zeroed,model-based-zeroed,oracle --paired interrogator-in-service \
        --out out/evaluate-in-service-learned                       # the shipped A (rule 144) on task v3
    cof-gym evaluate --suite experiments/suites/v2_heldout_grid.json --env CofGym/TorqueInterrogationInService-v3 \
        --agents (as above) --paired interrogator-in-service --out out/evaluate-in-service-heldout-learned
    cof-gym evaluate --agents interrogator-in-service,interrogator --out out/evaluate-v2-learned-v3
    cof-gym evaluate --suite experiments/suites/v2_heldoutK_grid.json --env CofGym/TorqueInterrogationInService-v3 \
        --agents (as above) --paired interrogator-in-service \
        --out out/evaluate-in-service-heldoutK-learned             # K: 2 ... 7, the other held-out grids on v3
    cof-gym evaluate --suite paper --episodes 5                                     # the paper's setting
    cof-gym evaluate --suite experiments/suites/v1_default.json --episodes 60 --out out/evaluate-v1
    cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout   # v1 held-out
    cof-gym bench --seconds 10 --markdown out/bench.md
    cof-gym evaluate --env-kwargs max_windows:45 --agents oracle,phase-rule,robust-model,interrogator  # the horizon's part:
    cof-gym evaluate --env-kwargs max_windows:60 --agents oracle,phase-rule,robust-model,interrogator  # the default suite and
    cof-gym evaluate --suite experiments/suites/v2_heldoutK_grid.json --env-kwargs max_windows:60 \
        --agents oracle,phase-rule,robust-model,interrogator    # each v2 held-out grid (K: "", 2 ... 7) with more steps
    python experiments/ppo_seeds.py --runs runs/ppo_lo_s0 runs/ppo_lo_s1 runs/ppo_lo_s2 --out out/ppo_seeds
    python experiments/train_interrogator.py --out runs/interrogator_wide_balance --climbs torque_wide=8000 \
        --guard-climbs torque_wide=8000 procedural_torque_wide=8000 --torque-balance-lag 65 --reuse \
        --add-guard-climbs runs/estimator_wide_balance/onpolicy_env_8e113d0ddec5.npz --probing-guard --ship   # rule 74
    python experiments/train_interrogator.py --out runs/interrogator_shipped --report-only   # the shipped agent per seed
    python experiments/crest_tradeoff.py --out out/crest_tradeoff.md
    python experiments/crest_tradeoff.py --run runs/interrogator_cm/ensemble --cautions 2 2.5 3 --targets 0.1 0.15 \
        --out out/crest_tradeoff_cm.md
    python experiments/crest_tradeoff.py --spread-cautions 0 1 2 4 --targets 0.1 --out out/crest_tradeoff_spread.md
    python experiments/crest_tradeoff.py --guards runs/interrogator_cm/ensemble --cautions 1.5 2 --targets 0.07 0.1 0.15 \
        --out out/crest_tradeoff_guard.md
    python experiments/crest_tradeoff.py --targets 0.1 --stops --out out/crest_tradeoff_stops.md
    python experiments/train_interrogator.py --out runs/interrogator_more --climbs env=8000 env_more=8000 --guard-climbs none
    python experiments/train_interrogator.py --out runs/interrogator_32k --climbs env=8000 env_more=24000 --guard-climbs none
    python experiments/learning_curve.py --run runs/interrogator_more --climbs env=8000 env_more=8000 \
        --sizes 2000 4000 8000 16000 --ensembles cof_gym/agents/policies/interrogator \
        runs/interrogator_more/ensemble runs/interrogator_32k/ensemble --out out/learning_curve.md
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_more/ensemble \
        runs/interrogator_32k/ensemble --targets 0.1 --stops --out out/crest_tradeoff_data.md
    python experiments/crest_tradeoff.py --own-climb --run cof_gym/agents/policies/interrogator \
        runs/interrogator_more/ensemble runs/interrogator_32k/ensemble --out out/crest_tradeoff_own.md
    python experiments/crest_tradeoff.py --run runs/interrogator_more/ensemble runs/interrogator_32k/ensemble \
        --guards cof_gym/agents/policies/interrogator --targets 0.1 --out out/crest_tradeoff_data_guard.md
    python experiments/crest_tradeoff.py --own-climb --run runs/interrogator_more/ensemble \
        --guards cof_gym/agents/policies/interrogator --out out/crest_tradeoff_own_guard.md
    python experiments/train_interrogator.py --out runs/interrogator_procguard --climbs procedural=8000 --fit-only \
        --guard-climbs none
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_more/ensemble \
        --guards runs/interrogator_procguard/ensemble --targets 0.1 --out out/crest_tradeoff_procguard.md
    mkdir -p runs/interrogator_mixguard && cp runs/interrogator_more/climbs.npz \
        runs/interrogator_procguard/climbs_procedural.npz runs/interrogator_mixguard/
    python experiments/train_interrogator.py --out runs/interrogator_mixguard --climbs env=8000 procedural=8000 --fit-only \
        --guard-climbs none
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_more/ensemble \
        --guards runs/interrogator_mixguard/ensemble --targets 0.1 --out out/crest_tradeoff_mixguard.md
    python experiments/make_grids.py    # adds the confirmation grids (session 16); every other grid unchanged
    python experiments/train_interrogator.py --out runs/interrogator_s16 --reuse --guards runs/interrogator_mixguard/ensemble \
        --guard-climbs none   # the shipped networks copied to runs/interrogator_s16/seed_K first
    python experiments/crest_tradeoff.py --own-climb --run cof_gym/agents/policies/interrogator \
        runs/interrogator_s16/ensemble --grids confirmation --out out/crest_tradeoff_confirmation.md  # before session 16's ship
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator --guards runs/interrogator_mixguard/ensemble \
        --targets 0.1 --grids confirmation --out out/crest_tradeoff_confirmation_guard.md
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator --guards runs/interrogator_mixguard/ensemble \
        --cautions 1.5 2 --targets 0.07 0.1 --out out/crest_tradeoff_guarded_cautions.md
    mkdir -p runs/interrogator_steepguard && cp runs/interrogator/climbs.npz runs/interrogator/climbs_procedural.npz \
        runs/interrogator_steepguard/
    python experiments/train_interrogator.py --out runs/interrogator_steepguard \
        --climbs env=8000 procedural=8000 procedural_steep=8000 --fit-only --guard-climbs none
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator --guards runs/interrogator_steepguard/ensemble \
        --targets 0.1 --out out/crest_tradeoff_steepguard.md
    python experiments/make_grids.py    # adds the second confirmation set (session 17); every other grid unchanged
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 \
        --crest-fractions none 0.5 1 2 --targets 0.1 --stops --out out/crest_tradeoff_crest.md
    mkdir -p runs/interrogator_crest && cp runs/interrogator/climbs.npz runs/interrogator_crest/
    python experiments/train_interrogator.py --out runs/interrogator_crest --climbs env=8000 crest_shrink=8000 \
        --fit-only --guard-climbs none
    python experiments/crest_tradeoff.py --run runs/interrogator_crest/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --crest-fractions none 0.5 1 2 --targets 0.1 \
        --out out/crest_tradeoff_crestnet.md
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_crest/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --crest-fractions 1 2 3 --crest-once-crept --targets 0.1 \
        --stops --out out/crest_tradeoff_crept.md
    python experiments/crest_tradeoff.py --own-climb --run cof_gym/agents/policies/interrogator --stops \
        --out out/crest_tradeoff_shipped_stops.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --set creep_log_step=0.02 \
        creep_log_step=0.03 creep_log_step=0.045 creep_log_step=0.06 --targets 0.1 --out out/crest_tradeoff_creep_steps.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --set approach_fraction=0.25 \
        approach_fraction=0.5 creep_log_step=0.02 creep_log_step=0.03 --targets 0.1 --stops --out out/crest_tradeoff_approach.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --set max_log_step=0.25 \
        --targets 0.1 --stops --out out/crest_tradeoff_max_step.md
    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_steep_grid.json --all-episodes --summary \
        --levels 0.9 0.95 1 1.05 1.1 1.15 1.2 1.3 --hold-dc 0.7 [--counter-torque] --out out/amplitude_probe_held[_ct].md
    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_steep_grid.json --all-episodes --summary \
        --levels 0.643 0.679 0.714 0.75 0.786 0.821 0.857 0.929 --amplitude-ratio 0.4 [--counter-torque] \
        --out out/amplitude_probe_staircase[_ct].md
    mkdir -p runs/interrogator_cm && cp runs/interrogator/climbs.npz runs/interrogator_cm/
    python experiments/train_interrogator.py --out runs/interrogator_cm --features creepage_modulation \
        --guard-climbs none --fit-only
    python experiments/crest_tradeoff.py --run runs/interrogator_cm/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --targets 0.1 --stops --out out/crest_tradeoff_cm_guard.md
    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_steep_grid.json --all-episodes --summary \
        --levels 0.9 0.95 0.98 1 1.02 1.05 1.08 1.1 1.15 1.2 --hold-dc 0.85 --out out/amplitude_probe_held85.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --set 'estimate_from="filter"' 'estimate_from="guard"' 'estimate_from="pooled"' \
        --out out/crest_tradeoff_estimate.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --set 'estimate_from="pooled_at_headroom"' --out out/crest_tradeoff_estimate_headroom.md
    python experiments/crest_tradeoff.py --grids confirmation2 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --set 'estimate_from="filter"' 'estimate_from="pooled_at_headroom"' \
        --out out/crest_tradeoff_estimate_confirmation2.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse --ship   # rule 16: the shipped estimate
    (then every cof-gym evaluate command above again)
    python experiments/make_grids.py    # adds the third confirmation set (session 21); every other grid unchanged
    python experiments/train_estimator.py --policy cof_gym/agents/policies/interrogator --out runs/estimator
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator/ensemble --targets 0.1 --stops --set 'estimate_from="pooled_at_headroom"' \
        'estimate_from="estimator"' 'estimate_from="estimator_pooled"' --out out/crest_tradeoff_estimator.md
    python experiments/train_estimator.py --policy cof_gym/agents/policies/interrogator --out runs/estimator_family \
        --climbs env=8000
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_family/ensemble --targets 0.1 --stops --set 'estimate_from="pooled_at_headroom"' \
        'estimate_from="estimator"' 'estimate_from="estimator_pooled"' --out out/crest_tradeoff_estimator_family.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_family/ensemble runs/estimator/ensemble --targets 0.1 --stops \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_pooled_at_headroom"' \
        --out out/crest_tradeoff_estimator_headroom.md
    python experiments/crest_tradeoff.py --grids confirmation3 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --estimators runs/estimator_family/ensemble runs/estimator/ensemble --targets 0.1 --stops \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_pooled_at_headroom"' \
        --out out/crest_tradeoff_estimator_confirmation3.md
    python experiments/make_grids.py    # adds the fourth confirmation set (session 21); every other grid unchanged
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --set creep_release=null creep_release=0.3 creep_release=0.6 --out out/crest_tradeoff_release.md
    python experiments/crest_tradeoff.py --grids confirmation4 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --set creep_release=null creep_release=0.6 --return-digits 4 \
        --out out/crest_tradeoff_release_confirmation4.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --set approach_fraction=0.25 creep_until=0.12 creep_until=0.16 creep_until=0.2 creep_until=0.25 \
        --out out/crest_tradeoff_approach_until.md
    (the commands above ran before session 22's ship: rerun now, those without ``--set crest_floor=...`` play the
    shipped climb with its crest floor)
    python experiments/make_grids.py    # adds the fifth confirmation set (session 22); every other grid unchanged
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set crest_floor=false crest_floor=true --out out/crest_tradeoff_crest_floor.md
    python experiments/crest_tradeoff.py --grids confirmation5 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --return-digits 4 --set crest_floor=false crest_floor=true \
        --out out/crest_tradeoff_crest_floor_confirmation5.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse --ship   # rule 21: the crest floor
    (then every cof-gym evaluate command above again)
    python experiments/make_grids.py    # adds the sixth confirmation set (session 22); every other grid unchanged
    python experiments/train_interrogator.py --out runs/interrogator_cc --climbs env=8000 \
        --guard-climbs env=8000 procedural=8000 --features cycle_crest --fit-only
    cp cof_gym/agents/policies/interrogator/manifest.json runs/interrogator_cc/ensemble/
    cp -r runs/interrogator_cc/guard/ensemble runs/interrogator_cc/ensemble/guard_0
    python experiments/crest_tradeoff.py --own-climb --run cof_gym/agents/policies/interrogator \
        runs/interrogator_cc/ensemble --stops --return-digits 4 --out out/crest_tradeoff_cycle_crest.md
    (session 23: every command above ran before its ship; rerun now, those without ``--set runaway_estimate=...``
    play the shipped climb with its runaway estimate)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set runaway_estimate=false runaway_estimate=true \
        --out out/crest_tradeoff_runaway.md
    python experiments/crest_tradeoff.py --grids confirmation6 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --return-digits 4 --set runaway_estimate=false runaway_estimate=true \
        --out out/crest_tradeoff_runaway_confirmation6.md
    cof-gym evaluate --suite experiments/suites/v2_validation_grid.json --out out/runaway-validation \
        --agents staircase+plain,staircase+runaway,phase-rule+plain,phase-rule+runaway,model-based+plain,model-based+runaway,robust-model+plain,robust-model+runaway
    (the same with v2_validation_procedural_grid.json into out/runaway-validation-procedural and with
    v2_validation_steep_grid.json into out/runaway-validation-steep: rule 24)
    python experiments/make_grids.py    # adds the seventh confirmation set (session 24); every other grid unchanged
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set pace_caution=null pace_caution=0 pace_caution=0.5 \
        pace_caution=1 --out out/crest_tradeoff_pace.md    # rule 25
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set frequency_hz=5 frequency_hz=7.5 frequency_hz=10 \
        --out out/crest_tradeoff_frequency.md    # rule 26
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set knee_stop=null 'knee_stop="any"' 'knee_stop="slow_probe"' \
        --out out/crest_tradeoff_knee.md    # rule 27
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set crest_ceiling=false crest_ceiling=true \
        --out out/crest_tradeoff_ceiling.md    # rule 28
    python experiments/crest_tradeoff.py --grids confirmation7 --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --return-digits 4 --set crest_ceiling=false crest_ceiling=true \
        --out out/crest_tradeoff_ceiling_confirmation7.md    # rule 28 confirmed, adopted
    cof-gym evaluate --suite experiments/suites/v2_validation_grid.json --out out/ceiling-validation \
        --agents staircase,staircase+ceiling,phase-rule,phase-rule+ceiling,model-based,model-based+ceiling,robust-model,robust-model+ceiling
    (the same with v2_validation_procedural_grid.json into out/ceiling-validation-procedural and with
    v2_validation_steep_grid.json into out/ceiling-validation-steep: rule 29, before it registered the four with
    the ceiling; since then NAME+ceiling is NAME, and evaluate refuses the pair as one agent given twice)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --targets 0.1 --stops --return-digits 4 --set ceiling_stop=false ceiling_stop=true \
        --out out/crest_tradeoff_ceiling_stop.md    # rule 30
    python experiments/train_estimator.py --out runs/estimator_env --climbs env=8000    # rule 31 (rule 18's)
    python experiments/train_estimator.py --out runs/estimator_env_laplace --climbs env=8000 --loss laplace
        # (the on-policy climbs of runs/estimator_env/onpolicy_env_*.npz copied there first: the same climbs)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_env_laplace/ensemble --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator"' \
        --out out/crest_tradeoff_median_estimator.md    # rule 31
    (the same with --estimators runs/estimator_env/ensemble into out/crest_tradeoff_mean_estimator.md)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_env_laplace/ensemble --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_at_headroom"' \
        --out out/crest_tradeoff_median_at_headroom.md    # rule 32
    python experiments/train_estimator.py --out runs/estimator_mixed_laplace --climbs env=8000 procedural=4000 \
        --loss laplace    # (the family climbs of runs/estimator_env copied there first)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_mixed_laplace/ensemble --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_at_headroom"' \
        --out out/crest_tradeoff_mixed_median_at_headroom.md    # rule 33
    (the same with --grids confirmation8 into out/crest_tradeoff_mixed_median_at_headroom_confirmation8.md)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/estimator_mixed_laplace/ensemble --targets 0.1 --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_at_headroom"' \
        --out /tmp/rule33_validation.md --records out/records_rule33_validation.json
    python experiments/paired_comparison.py out/records_rule33_validation.json --out out/paired_rule33_validation.md
    (the same two with --grids confirmation8, records_rule33_confirmation8.json and paired_rule33_confirmation8.md)
    python experiments/train_interrogator.py --out runs/filter_laplace --climbs env=8000 --guard-climbs none \
        --loss laplace --fit-only
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/filter_laplace/ensemble --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator"' --out out/crest_tradeoff_laplace_filter.md
    python experiments/train_interrogator.py --out runs/speed_scaled --climbs speed_scaled=8000 \
        --guard-climbs speed_scaled=8000 procedural_speed_scaled=8000 --fit-only   # rule 34
    python experiments/crest_tradeoff.py --run runs/speed_scaled/ensemble --guards runs/speed_scaled/guard/ensemble \
        --guards-only --targets 0.1 --stops --return-digits 4 --set frequency_reference_m_s=null \
        frequency_reference_m_s=15 frequency_reference_m_s=20 --records out/records_rule34_validation.json \
        --out out/crest_tradeoff_speed_scaled.md
    python experiments/indistinguishable_peaks.py --counter-torque --out out/indistinguishable_peaks.md
    python experiments/train_interrogator.py --out runs/climb_fit --climbs env=8000 --features climb_fit \
        --guard-climbs none --fit-only   # rule 35
    python experiments/feature_block_nll.py --climbs runs/climb_fit/climbs.npz --blocks none climb_fit \
        --out out/feature_block_nll.md
    python experiments/crest_tradeoff.py --run runs/climb_fit/ensemble --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --return-digits 4 --records out/records_rule35_validation.json \
        --out out/crest_tradeoff_climb_fit.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only \
        --estimators runs/climb_fit/ensemble --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled_at_headroom"' 'estimate_from="estimator_pooled_at_headroom"' \
        'estimate_from="estimator_at_headroom"' --records out/records_rule36_validation.json \
        --out out/crest_tradeoff_climb_fit_estimator.md   # rule 36
    python experiments/train_interrogator.py --out runs/filter_onpolicy --climbs env=8000 \
        --add-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz --guard-climbs none --fit-only   # rule 37
    python experiments/crest_tradeoff.py --run runs/filter_onpolicy/ensemble --guards cof_gym/agents/policies/interrogator/guard_0 \
        --guards-only --targets 0.1 --stops --return-digits 4 --records out/records_rule37_validation.json \
        --out out/crest_tradeoff_filter_onpolicy.md
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/filter_onpolicy/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids confirmation9 --records out/records_rule37_confirmation9.json \
        --out out/crest_tradeoff_filter_onpolicy_confirmation9.md
    python experiments/paired_comparison.py out/records_rule37_confirmation9.json --out out/paired_rule37_confirmation9.md
    python experiments/make_grids.py   # adds the tenth confirmation set (session 28); every other grid unchanged
    python experiments/train_interrogator.py --out runs/filter_onpolicy_mixed --climbs env=8000 --add-climbs \
        runs/estimator_env/onpolicy_env_56d6d6f9b007.npz runs/estimator_mixed_laplace/onpolicy_procedural_56d6d6f9b007.npz \
        --guard-climbs none --fit-only   # rule 38
    python experiments/crest_tradeoff.py --run runs/filter_onpolicy_mixed/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_rule38_validation.json --out out/crest_tradeoff_filter_onpolicy_mixed.md
    mkdir -p runs/dagger1 && cp -r cof_gym/agents/policies/interrogator runs/dagger1/policy \
        && cp runs/filter_onpolicy/ensemble/member_*.npz runs/dagger1/policy/   # rule 39: rule 37's filter, shipped guard
    python experiments/train_estimator.py --policy runs/dagger1/policy --out runs/dagger1 --climbs env=8000 --collect-only
    python experiments/train_interrogator.py --out runs/dagger1/fit --climbs env=8000 --add-climbs \
        runs/estimator_env/onpolicy_env_56d6d6f9b007.npz runs/dagger1/onpolicy_env_89f7136d2b1d.npz \
        --guard-climbs none --fit-only
    python experiments/crest_tradeoff.py --run runs/dagger1/fit/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_rule39_validation.json --out out/crest_tradeoff_dagger1.md
    python experiments/train_interrogator.py --out runs/guard_onpolicy --climbs env=8000 \
        --guard-climbs env=8000 procedural=8000 --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz \
        runs/estimator_mixed_laplace/onpolicy_procedural_56d6d6f9b007.npz --fit-only --reuse   # rule 40
        # (the shipped filter's member_K.npz copied to runs/guard_onpolicy/seed_K/member_0.npz first)
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/filter_onpolicy/ensemble \
        --guards runs/guard_onpolicy/guard/ensemble --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_rule40_validation.json --out out/crest_tradeoff_guard_onpolicy.md
    S=cof_gym/agents/policies/interrogator; C="caution 2, target 0.1, guards"; G=runs/guard_onpolicy/guard/ensemble
    python experiments/paired_comparison.py out/records_rule33_validation.json out/records_rule40_validation.json \
        --baseline "estimate_from pooled_at_headroom, $C $S/guard_0, estimators runs/estimator_mixed_laplace/ensemble" \
        --settings "$S, $C $G" "runs/filter_onpolicy/ensemble, $C $G" --out out/paired_rule40_validation.md
    python experiments/train_interrogator.py --out runs/guard_onpolicy_env --climbs env=8000 \
        --guard-climbs env=8000 procedural=8000 --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz \
        --fit-only --reuse   # rule 41 (the shipped filter's member_K.npz in seed_K/member_0.npz first)
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/filter_onpolicy/ensemble \
        --guards runs/guard_onpolicy_env/guard/ensemble --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_rule41_validation.json --out out/crest_tradeoff_guard_onpolicy_env.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --grids confirmation10 --records out/records_rule41_confirmation10_shipped.json \
        --out out/crest_tradeoff_shipped_confirmation10.md
    python experiments/crest_tradeoff.py --guards runs/guard_onpolicy_env/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --grids confirmation10 --records out/records_rule41_confirmation10.json \
        --out out/crest_tradeoff_guard_onpolicy_env_confirmation10.md
    python experiments/paired_comparison.py out/records_rule41_confirmation10_shipped.json \
        out/records_rule41_confirmation10.json --out out/paired_rule41_confirmation10.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse --ship   # rules 23 and 28
        # (the shipped networks copied to runs/interrogator/seed_K and guard/seed_K first: member_K.npz of
        # cof_gym/agents/policies/interrogator and of its guard_0; with every network there no climb is collected)
    python experiments/crest_tradeoff.py --guards runs/guard_onpolicy_env/guard/ensemble \
        runs/guard_onpolicy/guard/ensemble --guards-only --targets 0.1 --stops --return-digits 4 --set ceiling_stop=true \
        --records out/records_rule42_both_guards.json --out out/crest_tradeoff_rule42_both_guards.md   # rule 42 as written
    python experiments/crest_tradeoff.py --guards runs/guard_onpolicy_env/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --set ceiling_stop=true --records out/records_rule42_validation_A.json \
        --out out/crest_tradeoff_rule42_A.md
    python experiments/crest_tradeoff.py --guards runs/guard_onpolicy/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --set ceiling_stop=true --records out/records_rule42_validation_B.json \
        --out out/crest_tradeoff_rule42_B.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --grids confirmation11 --records out/records_rule42_confirmation11_shipped.json \
        --out out/crest_tradeoff_shipped_confirmation11.md   # with the shipped directory of commit f634051
    python experiments/crest_tradeoff.py --guards runs/guard_onpolicy_env/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --set ceiling_stop=true --grids confirmation11 \
        --records out/records_rule42_confirmation11.json --out out/crest_tradeoff_rule42_confirmation11.md
    python experiments/paired_comparison.py out/records_rule42_confirmation11_shipped.json \
        out/records_rule42_confirmation11.json --out out/paired_rule42_confirmation11.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse \
        --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz --ship   # rule 42 adopted
        # (rule 41's guard, runs/guard_onpolicy_env/guard/seed_K/member_0.npz, copied to runs/interrogator/guard/seed_K
        # first with the guard/training.json that this command writes; the filter's training.json likewise)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --records out/records_shipped_validation_session30.json \
        --out out/crest_tradeoff_shipped_validation_session30.md   # the shipped agent since rule 42
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 \
        runs/interrogator_probing_guard_backup/ensemble --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_rule43_validation.json --out out/crest_tradeoff_rule43.md   # rule 43
        # (runs/interrogator_probing_guard_backup/ensemble: commit f634051's guard_0 networks)
    python experiments/paired_comparison.py out/records_shipped_validation_session30.json \
        out/records_rule43_validation.json --out out/paired_rule43_validation.md
        # (every command above that plays cof_gym/agents/policies/interrogator without setting estimate_from: with
        # that directory as of commit af9b230, before rules 44 and 45; the commands below name what they change)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --set 'estimate_from="pooled"' 'estimate_from="guard"' \
        --records out/records_rule44_validation.json --out out/crest_tradeoff_rule44.md   # rule 44
    python experiments/paired_comparison.py out/records_shipped_validation_session30.json \
        out/records_rule44_validation.json --out out/paired_rule44_validation.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --set 'estimate_from="pooled_at_headroom"' 'estimate_from="pooled"' \
        --grids confirmation12 --records out/records_rule44_confirmation12.json \
        --out out/crest_tradeoff_rule44_confirmation12.md
    python experiments/paired_comparison.py out/records_rule44_confirmation12.json \
        --out out/paired_rule44_confirmation12.md
    G2="cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_probing_guard_backup/ensemble"
    python experiments/crest_tradeoff.py --guards $G2 --guards-only --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled"' --records out/records_rule45_validation.json \
        --out out/crest_tradeoff_rule45.md   # rule 45 (before its adoption: guard_0 the on-policy guard alone)
    B="estimate_from pooled, caution 2, target 0.1, guards cof_gym/agents/policies/interrogator/guard_0"
    python experiments/paired_comparison.py out/records_rule44_validation.json out/records_rule45_validation.json \
        --baseline "$B" --settings "$B, runs/interrogator_probing_guard_backup/ensemble" \
        --out out/paired_rule45_validation.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 --guards-only --targets 0.1 \
        --stops --return-digits 4 --set 'estimate_from="pooled"' --grids confirmation13 \
        --records out/records_rule45_confirmation13_shipped.json --out out/crest_tradeoff_shipped_confirmation13.md
    python experiments/crest_tradeoff.py --guards $G2 --guards-only --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled"' --grids confirmation13 --records out/records_rule45_confirmation13.json \
        --out out/crest_tradeoff_rule45_confirmation13.md
    python experiments/paired_comparison.py out/records_rule45_confirmation13_shipped.json \
        out/records_rule45_confirmation13.json --out out/paired_rule45_confirmation13.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse \
        --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz --probing-guard --ship   # rules 44, 45
        # (runs/interrogator_probing_guard_backup/seed_K copied to runs/interrogator/probing_guard/seed_K first)
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 \
        cof_gym/agents/policies/interrogator/guard_1 --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_shipped_validation_session31.json \
        --out out/crest_tradeoff_shipped_validation_session31.md   # the shipped agent since rule 45
    (then every cof-gym evaluate command above again)
    G="cof_gym/agents/policies/interrogator/guard_0 cof_gym/agents/policies/interrogator/guard_1"
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="guard"' --records out/records_rule46_validation.json --out out/crest_tradeoff_rule46.md
    python experiments/paired_comparison.py out/records_shipped_validation_session31.json \
        out/records_rule46_validation.json --out out/paired_rule46_validation.md
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="pooled"' 'estimate_from="guard"' --grids confirmation14 \
        --records out/records_rule46_confirmation14.json --out out/crest_tradeoff_rule46_confirmation14.md
    python experiments/paired_comparison.py out/records_rule46_confirmation14.json \
        --baseline "estimate_from pooled, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule46_confirmation14.md
    python experiments/train_interrogator.py --out runs/interrogator --reuse \
        --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz --probing-guard --ship   # rule 46
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_shipped_validation_session32.json \
        --out out/crest_tradeoff_shipped_validation_session32.md   # the shipped agent since rule 46
    (then every cof-gym evaluate command above again)
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set 'estimate_from="guard"' 'guard_cautions=[2, 1.5]' 'guard_cautions=[2, 2.5]' 'guard_cautions=[2, 3]' \
        --records out/records_rule47_validation.json --out out/crest_tradeoff_rule47.md
    python experiments/paired_comparison.py out/records_rule46_validation.json out/records_rule47_validation.json \
        --baseline "estimate_from guard, caution 2, target 0.1, guards ${G/ /, }" --out out/paired_rule47_validation.md
    cof-gym evaluate --suite experiments/suites/v2_heldout7_grid.json --out out/evaluate-v2-heldout7   # session 33
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set ceiling_fall_z=0 ceiling_fall_z=0.5 ceiling_fall_z=1 ceiling_fall_z=2 \
        --records out/records_rule48_validation.json --out out/crest_tradeoff_rule48.md
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set ceiling_fall_z=0 ceiling_fall_z=0.5 ceiling_fall_z=1 ceiling_fall_z=2 --scenario noise_level=3 \
        --records out/records_rule48_validation_noise3.json --out out/crest_tradeoff_rule48_noise3.md
    python experiments/paired_comparison.py out/records_rule48_validation.json \
        --baseline "ceiling_fall_z 0, caution 2, target 0.1, guards ${G/ /, }" --out out/paired_rule48_validation.md
    python experiments/paired_comparison.py out/records_rule48_validation_noise3.json \
        --baseline "ceiling_fall_z 0, caution 2, target 0.1, guards ${G/ /, }" --out out/paired_rule48_validation_noise3.md
    S49="ceiling_fall_z=0 ceiling_fall_z=1 ceiling_fall_z=2 ceiling_near_headroom=0.3 ceiling_near_headroom=0.5"
    B49="ceiling_fall_z 0, ceiling_near_headroom 0.3, caution 2, target 0.1, guards ${G/ /, }"
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 --set $S49 \
        --records out/records_rule49_validation.json --out out/crest_tradeoff_rule49.md
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 --set $S49 \
        --scenario noise_level=3 --records out/records_rule49_validation_noise3.json --out out/crest_tradeoff_rule49_noise3.md
    python experiments/paired_comparison.py out/records_rule49_validation.json --baseline "$B49" \
        --out out/paired_rule49_validation.md   # and the same for _noise3
    C49="ceiling_fall_z=0 ceiling_fall_z=2 ceiling_near_headroom=0.5"
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 --set $C49 \
        --grids confirmation15 --records out/records_rule49_confirmation15.json \
        --out out/crest_tradeoff_rule49_confirmation15.md   # and with --scenario noise_level=3: ..._noise3
    python experiments/paired_comparison.py out/records_rule49_confirmation15.json \
        --baseline "ceiling_fall_z 0, ceiling_near_headroom 0.5, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule49_confirmation15.md   # and the same for _noise3
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 --set $C49 \
        --grids confirmation16 --records out/records_rule50_confirmation16.json \
        --out out/crest_tradeoff_rule50_confirmation16.md   # and with --scenario noise_level=3: ..._noise3
    python experiments/paired_comparison.py out/records_rule50_confirmation16.json \
        --baseline "ceiling_fall_z 0, ceiling_near_headroom 0.5, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule50_confirmation16.md   # and the same for _noise3
    python experiments/train_interrogator.py --out runs/interrogator --reuse \
        --add-guard-climbs runs/estimator_env/onpolicy_env_56d6d6f9b007.npz --probing-guard --ship   # rule 50
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_shipped_validation_session33.json \
        --out out/crest_tradeoff_shipped_validation_session33.md   # the shipped agent since rule 50 (and with
        # --scenario noise_level=3: records_shipped_validation_session33_noise3, ..._session33_noise3.md)
    python experiments/train_interrogator.py --out runs/noise_guard --climbs noisy=8000 procedural_noisy=8000 \
        --guard-climbs none --fit-only   # rule 51's networks
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_shipped_validation_session34.json \
        --out out/crest_tradeoff_shipped_validation_session34.md   # and with --scenario noise_level=3 (_noise3)
        # or --scenario motor_lag_s=0.1 (_lag01) in both file names
    python experiments/crest_tradeoff.py --guards $G runs/noise_guard/ensemble --guards-only --targets 0.1 --stops \
        --return-digits 4 --records out/records_rule51A_validation.json \
        --out out/crest_tradeoff_rule51A_validation.md   # and _noise3, _lag01 as above; B: --run runs/noise_guard/ensemble
        # --guards $G ..., records_rule51B_validation*.json, crest_tradeoff_rule51B_validation*.md
    python experiments/paired_comparison.py out/records_shipped_validation_session34.json \
        out/records_rule51A_validation.json --out out/paired_rule51A_validation.md   # each scenario, A and B
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set creep_while_std=0.08 creep_while_std=0.16 --cautions 1.5 2 --records out/records_noise_pace_session34.json \
        --out out/crest_tradeoff_noise_pace_session34.md   # and with --scenario noise_level=3 (_noise3)
    python experiments/noise_reading.py --levels 0 0.5 1 1.5 2 3 --episodes 48   # rule 52's noise reference
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_reference_nms=0.4 noise_caution_exponent=0 noise_caution_exponent=0.35 \
        noise_caution_exponent=0.7 noise_creep_exponent=0 noise_creep_exponent=0.85 --scenario noise_level=3 \
        --records out/records_rule52_validation_noise3.json \
        --out out/crest_tradeoff_rule52_validation_noise3.md   # rule 52; and without --scenario and _noise3
    python experiments/paired_comparison.py out/records_shipped_validation_session34_noise3.json \
        out/records_rule52_validation_noise3.json --out out/paired_rule52_validation_noise3.md   # and without _noise3
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_reference_nms=0.4 noise_caution_exponent=0.1 noise_caution_exponent=0.2 \
        noise_creep_exponent=0.5 noise_creep_exponent=0.85 --scenario noise_level=3 \
        --records out/records_rule53_validation_noise3.json \
        --out out/crest_tradeoff_rule53_validation_noise3.md   # rule 53; and without --scenario and _noise3
    python experiments/paired_comparison.py out/records_shipped_validation_session34_noise3.json \
        out/records_rule53_validation_noise3.json --out out/paired_rule53_validation_noise3.md   # and without _noise3
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_reference_nms=null noise_reference_nms=0.4 noise_caution_exponent=0.2 noise_creep_exponent=0.85 \
        --grids confirmation17 --scenario noise_level=3 --records out/records_rule53_confirmation17_noise3.json \
        --out out/crest_tradeoff_rule53_confirmation17_noise3.md   # and without --scenario and _noise3
    python experiments/paired_comparison.py out/records_rule53_confirmation17_noise3.json \
        --baseline "noise_reference_nms None, noise_caution_exponent 0.2, noise_creep_exponent 0.85, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule53_confirmation17_noise3.md   # and the same without _noise3
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_se_reported=false noise_se_reported=true --scenario noise_level=2 \
        --records out/records_rule54_validation_noise2.json \
        --out out/crest_tradeoff_rule54_validation_noise2.md   # rule 54; and noise_level=3 (_noise3),
        # motor_lag_s=0.1 (_lag01), without --scenario (no suffix)
    python experiments/paired_comparison.py out/records_rule54_validation_noise2.json \
        --baseline "noise_se_reported False, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule54_validation_noise2.md   # and _noise3, _lag01, no suffix
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_se_reported=true noise_caution_exponent=0.1 noise_caution_exponent=0.2 \
        noise_creep_exponent=0.5 noise_creep_exponent=0.85 --scenario noise_level=2 \
        --records out/records_rule55_validation_noise2.json \
        --out out/crest_tradeoff_rule55_validation_noise2.md   # rule 55; and _noise3, _lag01, no suffix as above
    python experiments/paired_comparison.py out/records_rule54_validation_noise2.json \
        out/records_rule55_validation_noise2.json --baseline "noise_se_reported False, caution 2, target 0.1, guards ${G/ /, }" \
        --settings "noise_se_reported True, noise_caution_exponent 0.1, noise_creep_exponent 0.5, caution 2, target 0.1, guards ${G/ /, }" \
        "noise_se_reported True, noise_caution_exponent 0.1, noise_creep_exponent 0.85, caution 2, target 0.1, guards ${G/ /, }" \
        "noise_se_reported True, noise_caution_exponent 0.2, noise_creep_exponent 0.5, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule55_validation_noise2.md   # and _noise3
    (then every cof-gym evaluate command above again)   # session 37: the macro-slip = 100 % rows
    python experiments/estimate_interval.py --write --out out/estimate_interval.md   # session 43
    python experiments/knee_twins.py --counter-torque --out out/knee_twins.md   # session 37
    python experiments/knee_twins.py --counter-torque --ratio 1.25 --out out/knee_twins_125.md
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set crest_probe_lag_rise_deg=null crest_probe_lag_rise_deg=30 crest_probe_lag_rise_deg=45 \
        crest_probe_lag_rise_deg=60 --records out/records_rule56_validation.json \
        --out out/crest_tradeoff_rule56_validation.md   # rule 56; and --scenario noise_level=2 (_noise2)
    python experiments/paired_comparison.py out/records_rule56_validation.json \
        --baseline "crest_probe_lag_rise_deg None, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule56_validation.md   # and _noise2
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set crest_probe_lag_rise_deg=null crest_probe_lag_rise_deg=30 crest_probe_max_lag_deg=85 \
        crest_probe_max_lag_step_deg=10 --records out/records_rule57_validation.json \
        --out out/crest_tradeoff_rule57_validation.md   # rule 57; and --scenario noise_level=2 (_noise2)
    python experiments/paired_comparison.py out/records_rule57_validation.json --baseline "crest_probe_lag_rise_deg \
        None, crest_probe_max_lag_deg 85, crest_probe_max_lag_step_deg 10, caution 2, target 0.1, guards ${G/ /, }" \
        --out out/paired_rule57_validation.md   # and _noise2
    (rule 57's two commands again with --set ... crest_probe_lag_rise_deg=40 crest_probe_lag_rise_deg=45 in place of
        crest_probe_lag_rise_deg=30, and _rule58 in place of _rule57)   # rule 58 (session 39); and _noise2
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set crest_probe_lag_rise_deg=null crest_probe_lag_rise_deg=40 crest_probe_max_lag_deg=85 \
        crest_probe_max_lag_step_deg=10 crest_probe_max_noise_ratio=1 --records out/records_rule59_validation.json \
        --out out/crest_tradeoff_rule59_validation.md   # rule 59; --scenario noise_level=2 (_noise2); --grids
        # confirmation18 (_confirmation18)
    python experiments/paired_comparison.py out/records_rule59_validation.json --baseline "crest_probe_lag_rise_deg \
        None, crest_probe_max_lag_deg 85, crest_probe_max_lag_step_deg 10, crest_probe_max_noise_ratio 1, caution 2, \
        target 0.1, guards ${G/ /, }" --out out/paired_rule59_validation.md   # and _noise2, _confirmation18
    (rule 59's two commands again with --set ... crest_probe_max_noise_ratio=1 crest_probe_max_noise_ratio=null
        ... crest_probe_hold_crest=true, the baseline "... crest_probe_hold_crest True, ...", _rule60 in place of
        _rule59, --grids confirmation19 and _confirmation19 in place of the eighteenth)   # rule 60; and _noise2
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.2 0.3 0.4 --crest-fractions 0.25 0.5 \
        --stops --return-digits 4 --records out/records_rule61_validation.json \
        --out out/crest_tradeoff_rule61_validation.md   # rule 61
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --set noise_torque_measured=false noise_torque_measured=true --records out/records_rule62_validation.json \
        --out out/crest_tradeoff_rule62_validation.md   # rule 62; --scenario motor_lag_s=0.1 (_lag01)
    python experiments/paired_comparison.py out/records_rule62_validation.json --baseline "noise_torque_measured \
        False, caution 2, target 0.1, guards ${G/ /, }" --out out/paired_rule62_validation.md   # and _lag01
    (rule 62's two commands again with --set lag_floor=null lag_floor=0.65 lag_floor=0.45, the baseline "lag_floor
        None, ...", _rule63 in place of _rule62)   # rule 63; and _lag01
    python experiments/estimate_interval.py --write --out out/estimate_interval.md   # session 44: the in-flight bound
    python experiments/sensor_sensitivity.py --out out/sensor_sensitivity.md   # session 44
    python experiments/sensor_sensitivity.py --agents phase-rule,phase-rule-gated,robust-model,robust-model-gated \
        --out out/sensor_sensitivity_gated.md   # session 65
    python experiments/sensor_sensitivity.py --agents \
        staircase-zeroed,model-based-zeroed,model-based-zeroed-knee,model-based-zeroed-knee-ar1 \
        --out out/sensor_sensitivity_zeroed.md   # session 75
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --records out/records_shipped_validation_session45.json \
        --out out/crest_tradeoff_shipped_validation_session45.md   # rule 64's reference; and with --scenario
        # torque_gain_error=-0.15 (_torque_low) or torque_gain_error=0.15 (_torque_high) in both file names
    (the same with --grids validation and --run runs/interrogator_torque/ensemble, and --guards $G (B),
        runs/interrogator_torque/guard/ensemble (C) or runs/interrogator_torque_D/guard/ensemble
        runs/interrogator_torque/guard/ensemble (D), records and tables out/records_rule64X_validation*.json,
        out/crest_tradeoff_rule64X_validation*.md)   # rule 64, candidates B, C and D
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule64B_validation.json out/records_rule64C_validation.json out/records_rule64D_validation.json \
        --out out/paired_rule64_validation.md   # and _torque_low, _torque_high
    python experiments/feature_block_nll.py --climbs runs/interrogator_torque/climbs_torque_wide.npz \
        --blocks none torque_free --out out/feature_block_nll_torque_free.md   # session 45
    (rule 64's candidate commands with --run runs/interrogator_torque_free/ensemble --guards
        runs/interrogator_torque_free_E/guard/ensemble runs/interrogator_torque_free/guard/ensemble, records and
        tables out/records_rule65E_validation*.json, out/crest_tradeoff_rule65E_validation*.md)   # rule 65
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule65E_validation.json --out out/paired_rule65E_validation.md   # and _torque_low, _torque_high
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids validation_torque --records out/records_shipped_validation_torque.json \
        --out out/crest_tradeoff_shipped_validation_torque.md   # and D's, E's networks (_rule64D_, _rule65E_)
    python experiments/paired_comparison.py out/records_shipped_validation_torque.json \
        out/records_rule64D_validation_torque.json out/records_rule65E_validation_torque.json \
        --out out/paired_validation_torque.md   # session 45, information only
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids confirmation20 --records out/records_shipped_rule66_confirmation20.json \
        --out out/crest_tradeoff_shipped_rule66_confirmation20.md   # rule 66; D's networks: _rule66D_; and
        # --grids torque_confirmation (_torque_confirmation)
    python experiments/paired_comparison.py out/records_shipped_rule66_confirmation20.json \
        out/records_rule66D_confirmation20.json --out out/paired_rule66_confirmation20.md   # and _torque_confirmation
    python experiments/crest_tradeoff.py --run runs/interrogator_torque/ensemble --guards \
        runs/interrogator_torque_D/guard/ensemble runs/interrogator_torque/guard/ensemble --guards-only \
        --cautions 2.25 2.5 --targets 0.1 --stops --return-digits 4 --grids validation \
        --records out/records_rule67_validation.json --out out/crest_tradeoff_rule67_validation.md   # rule 67; and
        # --grids validation_torque (_validation_torque)
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule67_validation.json --out out/paired_rule67_validation.md   # and the torque validation set's
    python experiments/crest_tradeoff.py --run runs/interrogator_torque/ensemble --guards \
        runs/interrogator_torque_D/guard/ensemble runs/interrogator_torque/guard/ensemble --guards-only \
        --set 'guard_cautions=[2.25, 2.25]' 'guard_cautions=[2.5, 2.5]' --targets 0.1 --stops --return-digits 4 \
        --grids validation --records out/records_rule68G_validation.json \
        --out out/crest_tradeoff_rule68G_validation.md   # rule 68's G1, G2; and --grids validation_torque
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule68G_validation.json --out out/paired_rule68G_validation.md   # and the torque validation set's
    python experiments/crest_tradeoff.py --run runs/interrogator_more/ensemble --guards \
        runs/interrogator_more_D/guard/ensemble runs/interrogator_more/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --grids validation --records out/records_rule68H_validation.json \
        --out out/crest_tradeoff_rule68H_validation.md   # rule 68's H; and --grids validation_torque
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule68H_validation.json --out out/paired_rule68H_validation.md   # and the torque validation set's
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_torque/ensemble \
        --guards cof_gym/agents/policies/interrogator/guard_0 cof_gym/agents/policies/interrogator/guard_1 \
        runs/interrogator_torque_D/guard/ensemble runs/interrogator_torque/guard/ensemble --guards-only --targets 0.1 \
        --stops --return-digits 4 --grids validation --records out/records_rule69D_validation.json \
        --out out/crest_tradeoff_rule69D_validation.md   # rule 69's U_D, X_D; _rule69H_: H's filter and guards
        # (runs/interrogator_more/ensemble, runs/interrogator_more_D/guard/ensemble runs/interrogator_more/guard/ensemble)
        # for U_H, X_H; each also with --grids validation_torque (_validation_torque)
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule69D_validation.json --out out/paired_rule69D_validation.md   # and _rule69H_, and the torque
        # validation set's (against out/records_shipped_validation_torque.json)
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids confirmation21 --records out/records_shipped_rule69_confirmation21.json \
        --out out/crest_tradeoff_shipped_rule69_confirmation21.md   # rule 69's confirmation; X_H: _rule69XH_ with
        # --run runs/interrogator_more/ensemble and --guards $G runs/interrogator_more_D/guard/ensemble
        # runs/interrogator_more/guard/ensemble; each also with --grids torque_confirmation2
    python experiments/paired_comparison.py out/records_shipped_rule69_confirmation21.json \
        out/records_rule69XH_confirmation21.json --out out/paired_rule69_confirmation21.md   # and torque_confirmation2
    python experiments/crest_tradeoff.py --guards $G --guards-only --set torque_balance=true --targets 0.1 --stops \
        --return-digits 4 --grids validation --records out/records_rule70T_validation.json \
        --out out/crest_tradeoff_rule70T_validation.md   # rule 70's T; and --grids validation_torque, confirmation22
        # and torque_confirmation3 (the shipped agent's rows there: _shipped_rule70_)
    python experiments/paired_comparison.py out/records_shipped_validation_session45.json \
        out/records_rule70T_validation.json --out out/paired_rule70T_validation.md   # and the torque validation
        # set's; out/paired_rule70_confirmation22.md and _torque_confirmation3 against the _shipped_rule70_ records
    python experiments/crest_tradeoff.py --guards $G --guards-only --set torque_balance_max_lag_deg=45 \
        torque_balance_max_lag_deg=65 --targets 0.1 --stops --return-digits 4 --grids validation \
        --records out/records_rule71_validation.json --out out/crest_tradeoff_rule71_validation.md   # rule 71 (the
        # shipped agent then: rule 70's T); and --grids validation_torque; T65 and the shipped agent on confirmation23
        # and torque_confirmation4 (_rule71T65_, _shipped_rule71_)
    python experiments/paired_comparison.py out/records_rule70T_validation.json out/records_rule71_validation.json \
        --out out/paired_rule71_validation.md   # and _validation_torque; _confirmation23 and _torque_confirmation4
        # against the _shipped_rule71_ records
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids validation --records out/records_shipped_validation_session47.json \
        --out out/crest_tradeoff_shipped_validation_session47.md   # rule 72's reference rows; and validation_torque;
        # KF: --run runs/interrogator_balance/ensemble (_rule72KF_); K: the same --run with --guards
        # runs/interrogator_balance/guard/ensemble runs/interrogator_balance/probing_guard/ensemble (_rule72K_)
    python experiments/paired_comparison.py out/records_shipped_validation_session47.json \
        out/records_rule72KF_validation.json --out out/paired_rule72KF_validation.md   # and _validation_torque, _rule72K_
        # rule 73: --run runs/interrogator_wide_balance/ensemble with --guards $G (_rule73WF_) or with --guards
        # runs/interrogator_wide_balance/guard/ensemble runs/interrogator_wide_balance/probing_guard/ensemble (_rule73W_)
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids confirmation24 --records out/records_shipped_rule73_confirmation24.json \
        --out out/crest_tradeoff_shipped_rule73_confirmation24.md   # rule 73's confirmation; W: _rule73W_ with W's
        # --run and --guards; each also with --grids torque_confirmation5
    python experiments/paired_comparison.py out/records_shipped_rule73_confirmation24.json \
        out/records_rule73W_confirmation24.json --out out/paired_rule73_confirmation24.md   # and torque_confirmation5
        # rule 74: the same two commands (_shipped_rule74_, _rule74W_, paired_rule74) with --grids confirmation25 and
        # torque_confirmation6
    mkdir -p runs/interrogator_until_session48 && git archive a6923b1 cof_gym/agents/policies/interrogator \
        | tar -x --strip-components=4 -C runs/interrogator_until_session48   # the networks shipped until session 48
    python experiments/crest_tradeoff.py --run runs/interrogator_until_session48 --guards \
        runs/interrogator_until_session48/guard_0 runs/interrogator_until_session48/guard_1 --guards-only --targets 0.1 \
        --stops --return-digits 4 --scenario noise_level=3 --records out/records_prev_noise_level_session48.json \
        --out out/crest_tradeoff_prev_noise_level_session48.md   # and the shipped agent (--guards $G, _shipped_), each
        # also with --scenario motor_lag_s=0.1 (_motor_lag_s_); paired_comparison.py prev -> shipped (paired_TAG_session48)
    python experiments/crest_tradeoff.py --guards $G --guards-only --targets 0.1 --stops --return-digits 4 \
        --grids validation --records out/records_shipped_validation_session48.json \
        --out out/crest_tradeoff_shipped_validation_session48.md   # rule 75's reference rows; and validation_torque;
        # V: --guards runs/interrogator_until_session48/guard_0 runs/interrogator_until_session48/guard_1 $G
        # (_rule75V_validation, _validation_torque, and _noise_level with --scenario noise_level=3), each paired
        # against the shipped agent's records of the same grids by paired_comparison.py (paired_rule75V_*)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set 'estimate_from="pooled"' \
        'estimate_from="filter"' --targets 0.1 --stops --return-digits 4 --grids validation \
        --records out/records_rule76_validation.json --out out/crest_tradeoff_rule76_validation.md   # rule 76; and
        # validation_torque, each paired against out/records_shipped_GRIDS_session48.json (paired_rule76_*)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set noise_caution_exponent=0.4 --targets 0.1 \
        --stops --return-digits 4 --grids validation --records out/records_rule77N_validation.json \
        --out out/crest_tradeoff_rule77N_validation.md   # rule 77's N; and validation_torque, and --scenario
        # noise_level=3 (_noise_level); Z: --set ceiling_fall_z=3 (_rule77Z_); each paired as rule 75's (paired_rule77*)
    mkdir -p runs/interrogator_noisy_wide && cp runs/interrogator_wide_balance/climbs*torque_wide.npz \
        runs/interrogator_noisy_wide/   # rule 78's M: W's three recipe steps (rule 73) with these collections
    python experiments/train_interrogator.py --out runs/interrogator_noisy_wide --climbs torque_wide=4000 \
        noisy_torque_wide=4000 --guard-climbs torque_wide=4000 noisy_torque_wide=4000 procedural_torque_wide=4000 \
        procedural_noisy_torque_wide=4000 --torque-balance-lag 65 --fit-only   # then assemble_policy.py,
        # train_estimator.py --collect-only (runs/estimator_noisy_wide) and the --reuse --probing-guard fit as rule 73's
    python experiments/crest_tradeoff.py --run runs/interrogator_noisy_wide/ensemble --guards \
        runs/interrogator_noisy_wide/guard/ensemble runs/interrogator_noisy_wide/probing_guard/ensemble --guards-only \
        --targets 0.1 --stops --return-digits 4 --grids validation --records out/records_rule78M_validation.json \
        --out out/crest_tradeoff_rule78M_validation.md   # and validation_torque, and --scenario noise_level=3
        # (_noise_level) and motor_lag_s=0.1 (_motor_lag_s), each paired against the shipped agent's session-48
        # records of the same plays by paired_comparison.py (paired_rule78M_*)
        # rule 79's P: the same in runs/interrogator_noisy_plus with --climbs torque_wide=8000 noisy_torque_wide=4000
        # and --guard-climbs torque_wide=8000 noisy_torque_wide=4000 procedural_torque_wide=8000
        # procedural_noisy_torque_wide=4000 (runs/estimator_noisy_plus), played and paired alike (_rule79P_)
    python experiments/crest_tradeoff.py --run runs/interrogator_noisy_plus/ensemble --guards $G --guards-only \
        --targets 0.1 --stops --return-digits 4 --grids validation_torque \
        --records out/records_swap79PF_validation_torque.json --out out/crest_tradeoff_swap79PF_validation_torque.md
        # information only: P's filter with the shipped guards (PF); the shipped filter with P's guards (PG: no --run,
        # --guards runs/interrogator_noisy_plus/guard/ensemble runs/interrogator_noisy_plus/probing_guard/ensemble);
        # each also with --scenario noise_level=3 (_noise_level), paired as rule 79's (paired_swap79*)
        # rule 80's Q: rule 79's commands in runs/interrogator_noisy_guard with --climbs torque_wide=8000 (the guard's
        # collections P's; runs/estimator_noisy_guard), played and paired alike (_rule80Q_)
    python experiments/crest_tradeoff.py --guards runs/interrogator_noisy_guard/guard/ensemble \
        runs/interrogator_noisy_guard/probing_guard/ensemble cof_gym/agents/policies/interrogator/guard_1 --guards-only \
        --targets 0.1 --stops --return-digits 4 --grids validation --records out/records_rule81R3_validation.json \
        --out out/crest_tradeoff_rule81R3_validation.md   # rule 81's R3; R4: --guards $G then Q's two (_rule81R4_);
        # each also with validation_torque, --scenario noise_level=3 and motor_lag_s=0.1, paired as rule 78's
        # rule 82: R3's commands with --set 'guard_cautions=[2, 2, 1.5]' (_rule82R3a_) or 'guard_cautions=[2, 2, 1.75]'
        # (_rule82R3b_); R3c: cof_gym/agents/policies/interrogator/guard_0 third (--set guard_cautions=null, _rule82R3c_)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set approach_fraction=0.25 --targets 0.1 --stops \
        --return-digits 4 --grids validation --records out/records_rule83A25_validation.json \
        --out out/crest_tradeoff_rule83A25_validation.md   # rule 83's A25; A50: approach_fraction=0.5 (_rule83A50_);
        # each also with validation_torque, --scenario noise_level=3 and motor_lag_s=0.1, paired as rule 78's
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_1 \
        runs/interrogator_noisy_guard/guard/ensemble runs/interrogator_noisy_guard/probing_guard/ensemble \
        --guards-only --targets 0.1 --stops --return-digits 4 --grids confirmation26 \
        --records out/records_rule84R3_confirmation26.json --out out/crest_tradeoff_rule84R3_confirmation26.md
        # rule 84; the shipped agent: --guards $G (_shipped_);
        # each also with --scenario noise_level=3 (_confirmation26_noise_level), motor_lag_s=0.1
        # (_confirmation26_motor_lag_s) and --grids torque_confirmation7; paired by paired_comparison.py
        # (paired_rule84R3_*)
    python experiments/rule_check.py out/records_shipped_confirmation26.json out/records_rule84R3_confirmation26.json \
        out/records_shipped_confirmation26_noise_level.json out/records_rule84R3_confirmation26_noise_level.json \
        out/records_shipped_confirmation26_motor_lag_s.json out/records_rule84R3_confirmation26_motor_lag_s.json \
        out/records_shipped_torque_confirmation7.json out/records_rule84R3_torque_confirmation7.json --gain \
        --out out/rule_check_rule84_a.md   # (b): the first and the last pair with --errors (rule_check_rule84_b.md)
    python experiments/train_interrogator.py --out runs/interrogator_filter_onpolicy --climbs torque_wide=8000 \
        --add-climbs runs/estimator_wide_balance/onpolicy_env_8e113d0ddec5.npz --guard-climbs none \
        --torque-balance-lag 65 --fit-only   # rule 85's F (the recipe's climbs_torque_wide.npz copied in first)
    python experiments/crest_tradeoff.py --run runs/interrogator_filter_onpolicy/ensemble --guards $G --guards-only \
        --targets 0.1 --stops --return-digits 4 --grids validation --records out/records_rule85F_validation.json \
        --out out/crest_tradeoff_rule85F_validation.md   # also validation_torque, --scenario noise_level=3
        # (_noise_level) and motor_lag_s=0.1 (_motor_lag_s), each paired against the session-48 records
        # (paired_rule85F_*); confirmation27 (at the draws, noise_level=3, motor_lag_s=0.1) and torque_confirmation8,
        # with the shipped agent beside it (no --run, _shipped_), paired alike
    python experiments/rule_check.py out/records_shipped_confirmation27.json out/records_rule85F_confirmation27.json \
        out/records_shipped_confirmation27_noise_level.json out/records_rule85F_confirmation27_noise_level.json \
        out/records_shipped_confirmation27_motor_lag_s.json out/records_rule85F_confirmation27_motor_lag_s.json \
        out/records_shipped_torque_confirmation8.json out/records_rule85F_torque_confirmation8.json --gain \
        --out out/rule_check_rule85_a.md   # (b): the first and the last pair with --errors (rule_check_rule85_b.md)
    python experiments/crest_tradeoff.py --run runs/interrogator_filter_onpolicy/ensemble --guards $G --guards-only \
        --cautions 2.25 --targets 0.1 --stops --return-digits 4 --grids validation \
        --records out/records_rule86c2.25_validation.json --out out/crest_tradeoff_rule86c2.25_validation.md
        # rule 86's candidates: --cautions 2.25, 2.5, 2.75 (_rule86cC_), each also with validation_torque,
        # --scenario noise_level=3 and motor_lag_s=0.1, paired against the session-48 records (paired_rule86cC_*)
    python experiments/rule_check.py out/records_shipped_validation_session48.json out/records_rule86c2.25_validation.json \
        out/records_shipped_validation_torque_session48.json out/records_rule86c2.25_validation_torque.json \
        out/records_shipped_noise_level_session48.json out/records_rule86c2.25_noise_level.json \
        out/records_shipped_motor_lag_s_session48.json out/records_rule86c2.25_motor_lag_s.json --strict-grid none \
        --out out/rule_check_rule86c2.25_selection.md   # and 2.5, 2.75 alike (rule 86's selection)
        # rule 86's decision: F at caution 2.25 and the shipped agent on confirmation28 (at the draws, noise_level=3,
        # motor_lag_s=0.1) and torque_confirmation9 (records _rule86_ and _shipped_), checked as rule 85's (a) and (b)
        # (rule_check_rule86_a, rule_check_rule86_b)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set creep_sticky_below=1.0 --targets 0.1 --stops \
        --return-digits 4 --grids validation --records out/records_rule87s1.0_validation.json \
        --out out/crest_tradeoff_rule87s1.0_validation.md   # rule 87's candidates 1.0 and 1.5 (_rule87s1.5_), each
        # also on validation_torque, --scenario noise_level=3 and motor_lag_s=0.1, paired against the session-48
        # records and checked as rule 86's selection (rule_check_rule87sV_selection)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set creep_sticky_below=1.5 --targets 0.1 --stops \
        --return-digits 4 --grids extremes_confirmation --records out/records_rule88C_extremes_confirmation.json \
        --out out/crest_tradeoff_rule88C_extremes_confirmation.md   # rule 88's C; the shipped agent without --set
        # (_shipped_); both also on validation_extremes, confirmation29 (at the draws, noise_level=3,
        # motor_lag_s=0.1) and torque_confirmation10, paired (paired_rule88C_*) and checked over the five decisive
        # pairs with --gain (rule_check_rule88_a) and --errors (rule_check_rule88_b)
    python experiments/crest_tradeoff.py --guards $G --guards-only --set creep_cautious_floor=0 --targets 0.1 --stops \
        --return-digits 4 --grids validation --records out/records_rule89K0_validation.json \
        --out out/crest_tradeoff_rule89K0_validation.md   # rule 89's K0; Kn (-0.05) and Kp (0.05) alike, each also
        # on validation_torque and --scenario noise_level=3 / motor_lag_s=0.1 (records _rule89KC_noise_level etc.)
    python experiments/rule_check.py out/records_shipped_validation_session48.json out/records_rule89K0_validation.json \
        --fewer-runaways --gain --returns --errors --error-grid family --out out/rule_check_rule89K0_i.md   # (i); (ii):
        # the torque pair with --returns --errors --error-grid family; (iii), (iv): noise and lag pairs with --returns
        # K0 also with --grids validation_extremes (records_rule89K0_validation_extremes), paired against
        # records_shipped_validation_extremes (paired_rule89K0_validation_extremes)
    A="phase-rule robust-model staircase model-based"   # the hand-built agents on the same four plays:
    python experiments/scripted_plays.py --agents $A --grids validation --records "out/records_{agent}_validation.json"
    python experiments/scripted_plays.py --agents $A --grids validation_torque \
        --records "out/records_{agent}_validation_torque.json"   # and --grids validation with --scenario
        # noise_level=3 (records _{agent}_noise_level) and motor_lag_s=0.1 (_{agent}_motor_lag_s)
    P() { printf '%s+' out/records_$1_{validation,validation_torque,noise_level,motor_lag_s}$2.json | sed 's/+$/\\n/'; }
    python experiments/frontier.py $(P shipped _session48) $(for c in 78M 79P 80Q 81R3 81R4 82R3a 82R3b 82R3c \
        83A25 83A50 85F 86c2.25 86c2.5 86c2.75 87s1.0 87s1.5 89Kn 89K0 89Kp; do P rule$c; done) \
        --references $(for a in $A; do P $a; done) --shipped $(P shipped _session48) \
        --out out/frontier_validation.md --figure docs/interrogator_frontier_validation.png   # every candidate of rules
        # 78-89 with the four validation plays, pooled, beside the hand-built agents (session 52)
        # rule 90: the shipped agent (--guards $G), P (--run runs/interrogator_noisy_plus/ensemble --guards
        # runs/interrogator_noisy_plus/guard/ensemble runs/interrogator_noisy_plus/probing_guard/ensemble) with
        # --guards-only --targets 0.1 --stops --return-digits 4 on --grids confirmation30 (and --scenario noise_level=3,
        # motor_lag_s=0.1), torque_confirmation11 and extremes_confirmation2 (records _shipped_ / _rule90P_), the
        # hand-built agents by scripted_plays.py on the same five (records _{agent}_), then:
    Q() { printf '%s+' out/records_$1_{confirmation30,confirmation30_noise_level,confirmation30_motor_lag_s,\
torque_confirmation11,extremes_confirmation2}.json | sed 's/+$/\\n/'; }
    python experiments/frontier.py $(Q shipped) $(Q rule90P) --references $(for a in $A; do Q $a; done) \
        --shipped $(Q shipped) --out out/frontier_rule90.md   # (a); (b) and (c): rule_check.py on the five pairs
        # (shipped, rule90P) with --gain --more-runaways 2352 (rule_check_rule90_b) and --errors --error-grid family
        # --returns --more-runaways 2352 (rule_check_rule90_c)
    python experiments/crest_tradeoff.py --run runs/interrogator_noisy_plus/ensemble --guards \
        runs/interrogator_noisy_plus/guard/ensemble runs/interrogator_noisy_plus/probing_guard/ensemble --guards-only \
        --cautions 2.25 --targets 0.1 --stops --return-digits 4 --grids validation \
        --records out/records_rule91P2.25_validation.json --out out/crest_tradeoff_rule91P2.25_validation.md
        # rule 91: P225 and P250 (--cautions 2.5), each also on validation_torque and --scenario noise_level=3 /
        # motor_lag_s=0.1; rule_check.py on the four pairs against the session-48 records with --gain
        # --more-runaways 1440 (rule_check_rule91PC_b) and --errors --error-grid family --returns --more-runaways 1440
        # (_c); frontier.py $(P shipped _session48) $(P rule91P2.25) $(P rule91P2.5) --references ... as above
        # (frontier_rule91_validation)
        # rule 92: the shipped agent (--guards $G --guards-only) with --estimators and --set estimate_from=SOURCE:
        # EF runs/interrogator_filter_onpolicy/ensemble estimator_pooled, EF1 the same with estimator, EP
        # runs/interrogator_noisy_plus/{ensemble,guard/ensemble,probing_guard/ensemble} estimator_pooled, EFP all four
        # estimator_pooled; each with --targets 0.1 --stops --return-digits 4 on the four validation plays (records
        # _rule92C_validation, _validation_torque, _noise_level, _motor_lag_s); rule_check.py on the four pairs against
        # the session-48 records with --errors --error-grid family --returns --more-runaways 1440
        # (rule_check_rule92C_c); frontier.py $(P shipped _session48) $(P rule92EF) $(P rule92EF1) $(P rule92EP)
        # $(P rule92EFP) --references ... as above (frontier_rule92_validation)
        # rule 93: the same with --estimators and --set estimate_from=guard_estimator_pooled: GP
        # runs/interrogator_noisy_plus/{guard,probing_guard}/ensemble, GQ runs/interrogator_noisy_guard/{guard,
        # probing_guard}/ensemble, GPQ all four (rule_check_rule93C_c; frontier_rule93_validation)
        # rule 93's confirmation: the shipped agent and GPQ (as above) on --grids confirmation31 (and --scenario
        # noise_level=3, motor_lag_s=0.1), torque_confirmation12 and extremes_confirmation3 (records _shipped_ /
        # _rule93GPQ_), the hand-built agents by scripted_plays.py on the same five (records _{agent}_), then
        # frontier.py $(Q shipped) $(Q rule93GPQ) --references ... --shipped $(Q shipped) (frontier_rule93), Q as for
        # rule 90 with the thirty-first sets, and rule_check.py on the five pairs with --errors --error-grid family
        # --returns --more-runaways 2352 (rule_check_rule93_c)
        # rule 94: the shipped agent (--guards $G --guards-only) with --set creep_sticky_below=1.0 (S10),
        # creep_release=0.3 / 0.45 / 0.6 (R30, R45, R60), --targets 0.1 --stops --return-digits 4 on the four validation
        # plays; rule_check.py against the session-48 records with --errors --error-grid family --returns
        # --more-runaways 1440 (rule_check_rule94C_c); frontier.py ... (frontier_rule94_validation)
        # rule 94's confirmation: runs/confirm94.sh R45 creep_release=0.45 as rule 93's with --set creep_release=0.45
        # in place of the estimators, on confirmation32 (and --scenario noise_level=3, motor_lag_s=0.1),
        # torque_confirmation13 and extremes_confirmation4 (frontier_rule94, rule_check_rule94_c)
        # rule 95: the shipped agent (rule 94's climb; records _rule95shipped53_) and --set ceiling_noise_z=0.5 / 1 / 2
        # (N05, N1, N2), each with --guards $G --guards-only --targets 0.1 --stops --return-digits 4 on the four
        # validation plays; rule_check.py against the _rule95shipped53_ records with --errors --error-grid family
        # --returns --more-runaways 1440 (rule_check_rule95C_c); frontier.py $(P rule95shipped53) $(P rule95N05)
        # $(P rule95N1) $(P rule95N2) --references ... --shipped $(P rule95shipped53) (frontier_rule95_validation)
        # rule 95's confirmation: runs/confirm95.sh N05 ceiling_noise_z=0.5, rule 94's script on confirmation33,
        # torque_confirmation14 and extremes_confirmation5 (frontier_rule95, rule_check_rule95_c)
        # rule 96: --set creep_sticky_below=1.0 / 1.5 (K10, K15) as rule 95's candidates, against the _rule95shipped53_
        # records (rule_check_rule96C_c; frontier.py $(P rule95shipped53) $(P rule96K10) $(P rule96K15) ...:
        # frontier_rule96_validation)
        # rule 97's exploration: runs/explore97{,b,c,d}.sh (--set rows on --grids confirmation31 and confirmation33,
        # records _x97shipped_, _x97pace_, _x97creep_, _x97cands_, _x97until_, _x97paceuntil_, _x97paceuntil2_), then
        # frontier.py $(X x97shipped) $(X x97pace) ... --references $(X phase-rule) ... --shipped $(X x97shipped), X
        # joining a name's two files by + (frontier_explore97)
        # rule 97: --set pace_caution=2.0 / 1.75 (P20, P175) and pace_caution=1.5 creep_until=0.2 (P15U20) as rule 95's
        # candidates, against the _rule95shipped53_ records (runs/rule97.sh: rule_check_rule97C_c; frontier.py
        # $(P rule95shipped53) $(P rule97P20) $(P rule97P175) $(P rule97P15U20) ...: frontier_rule97_validation)
        # rule 98: python experiments/train_interrogator.py --out runs/interrogator_applied --climbs torque_wide=8000
        # --guard-climbs torque_wide=8000 procedural_torque_wide=8000 --torque-balance-lag 65 --add-guard-climbs
        # runs/estimator_wide_balance/onpolicy_env_8e113d0ddec5.npz --probing-guard --features applied_amplitude
        # --fit-only (the caches copied from runs/interrogator_wide_balance), then A: --run
        # runs/interrogator_applied/ensemble --guards runs/interrogator_applied/{guard,probing_guard}/ensemble
        # --guards-only --targets 0.1 --stops --return-digits 4 on the four validation plays (runs/rule98.sh:
        # rule_check_rule98A_c against the _rule95shipped53_ records, frontier_rule98_validation)
        # after rule 98: runs/explore99.sh (A, AS with --guards adding cof_gym/agents/policies/interrogator/guard_{0,1},
        # AC with --set guard_cautions=[2.25,2.25]; --grids confirmation33, with --scenario motor_lag_s=0.1, and
        # torque_confirmation14), then frontier.py $(X shipped) $(X x99A) $(X x99AS) $(X x99AC) --references ...,
        # X joining a name's three files by + (frontier_explore99)
        # rule 99's exploration: runs/explore99b.sh (the shipped climb and guards with --estimators
        # runs/interrogator_applied/{guard,probing_guard}/ensemble and --set estimate_from=estimator (E) or
        # guard_estimator_pooled (EG), EA with runs/interrogator_applied/ensemble as a third estimator; the same three
        # sets), then frontier.py $(X shipped) $(X x99E) $(X x99EA) $(X x99EG) ... (frontier_explore99b)
        # rule 99: E and EG as in the exploration, --guards $G --guards-only --targets 0.1 --stops --return-digits 4 on
        # the four validation plays (runs/rule99.sh: rule_check_rule99C_c against the _rule95shipped53_ records,
        # frontier_rule99_validation)
        # rule 100's exploration: runs/explore100.sh (AF: --run runs/interrogator_applied/ensemble --guards $G; AG:
        # --guards runs/interrogator_applied/{guard,probing_guard}/ensemble) and runs/explore100b.sh (AFE: AF with
        # E's --estimators and --set estimate_from=estimator), the same three sets, then frontier.py $(X shipped)
        # $(X x99A) $(X x100AF) $(X x100AG) $(X x100AFE) $(X x99E) ... (frontier_explore100)
        # rule 100: AFE as in the exploration with --targets 0.1 --stops --return-digits 4 on the four validation plays
        # (runs/rule100.sh: rule_check_rule100AFE_c against the _rule95shipped53_ records, frontier_rule100_validation)
        # rule 101: python experiments/train_estimator.py --policy runs/policy_applied --set ceiling_stop=false --out
        # runs/estimator_applied --climbs env=8000 procedural=4000 --collect-only (runs/policy_applied: A's filter as
        # members, its guard and probing guard as guard_0 and guard_1, the shipped manifest), then rule 98's fit with
        # --reuse into runs/interrogator_applied_own (--add-guard-climbs the env cache: A2) and
        # runs/interrogator_applied_proc (both caches: A3), A's filter, probing guard and caches copied in; A2 and A3
        # as A with their guard 0 on the four validation plays (runs/rule101.sh: rule_check_rule101{A2,A3}_c against
        # the _rule95shipped53_ records, frontier_rule101_validation, its frontier.py with --rows)
        # after rule 101: runs/explore102.sh (A2, A3, A3E with --estimators A2's guard 0 and the probing guard and --set
        # estimate_from=estimator, A23 with both guards 0 and the probing guard; --grids confirmation33, with --scenario
        # noise_level=3 and motor_lag_s=0.1, and torque_confirmation14), then frontier.py $(X shipped) $(X x102A2) ...,
        # X joining a name's four files by + (frontier_explore102)
        # rule 102: rule_check.py on rule 99's EG validation records against the _rule95shipped53_ ones with --gain
        # --errors --error-grid family --returns --more-runaways 1440 --same-climbs (rule_check_rule102EG_validation);
        # runs/confirm102.sh (the shipped agent and EG, --estimators runs/interrogator_applied/{guard,probing_guard}/
        # ensemble --set estimate_from=guard_estimator_pooled, and scripted_plays.py's four agents on confirmation34 at
        # its draws, --scenario noise_level=3 and motor_lag_s=0.1, torque_confirmation15 and extremes_confirmation6;
        # frontier_rule102 with frontier.py --rows, rule_check_rule102 with --more-runaways 2352 --same-climbs)
        # rule 103: python experiments/train_estimator.py --set ceiling_stop=false --out runs/estimator_shipped_proc
        # --climbs procedural=4000 --collect-only, then the shipped recipe's fit with --reuse into
        # runs/interrogator_shipped_proc (runs/interrogator_wide_balance's filter, probing guard and caches copied in)
        # and --add-guard-climbs runs/estimator_wide_balance/onpolicy_env_8e113d0ddec5.npz and the procedural cache;
        # S3: --guards runs/interrogator_shipped_proc/guard/ensemble cof_gym/agents/policies/interrogator/guard_1 on the
        # four validation plays (runs/rule103.sh: rule_check_rule103S3_c, frontier_rule103_validation with --rows)
        # rule 104: python experiments/learned_caution.py --out runs/caution_rl --seeds 0 1 2 3 4, then each seed K on
        # the four validation plays (python experiments/validation_plays.py rule104LK --caution-policy
        # runs/caution_rl/seed_K/model.zip: records out/records_rule104LK_*), learned_caution.py --report with the
        # five seeds' plays and --baseline the _rule95shipped53_ ones (learned_caution_rule104), frontier.py with the
        # five seeds and --rows
        # (frontier_rule104_validation), rule_check.py for seed 0 (rule_check_rule104L0_c); validation_plays.py with
        # --confirmation confirmation35 torque_confirmation16 extremes_confirmation7 for shipped, for rule104L0 (its
        # --caution-policy) and with --hand-built (the five plays: the set at its draws, --scenario noise_level=3 and
        # motor_lag_s=0.1, the torque and the extremes set;
        # frontier_rule104 with frontier.py --rows, rule_check_rule104 with --more-runaways 2352)
        # rule 105: python experiments/learned_caution.py --out runs/caution_rl_long --seeds 0 --timesteps 200000, then
        # validation_plays.py rule105L --caution-policy runs/caution_rl_long/seed_0/model.zip (its four plays,
        # frontier_rule105_validation beside rule 104's seed 0 with --rows, rule_check_rule105L_c)
        # rule 106: python experiments/learned_caution.py --paired --episodes 200 (the budget), then
        # python experiments/learned_caution.py --out runs/caution_lagrangian --seeds 0 1 2 3 4 --cost-budget 0.085;
        # the shipped agent (records _rule95shipped53_) and each seed K with --caution-policy
        # runs/caution_lagrangian/seed_K/model.zip on the four validation plays as rule 104's (records _rule106LK_),
        # the hand-built agents' four (validation_plays.py --hand-built); learned_caution.py --report
        # (learned_caution_rule106), frontier.py with the five seeds, the references and --rows
        # (frontier_rule106_validation), rule_check.py for seed 3, the best return (rule_check_rule106L3_c)
        # rule 107: validation_plays.py rule107E --caution-policy with the five seeds' models joined by +
        # (records _rule107E_), frontier.py with rule 106's seed 3 and --rows (frontier_rule107_validation),
        # rule_check_rule107E_c
        # rule 108: learned_caution.py --out runs/caution_lagrangian_tight --seeds 0 1 2 3 4 --cost-budget 0.06, each
        # seed on the four validation plays (validation_plays.py rule108TK --caution-policy MODEL), --report
        # (learned_caution_rule108)
        # rule 109: learned_caution.py --out runs/caution_lagrangian_long --seeds 0 1 2 --timesteps 200000
        # --cost-budget 0.07, each seed on the four validation plays (python experiments/validation_plays.py rule109LK
        # --caution-policy runs/caution_lagrangian_long/seed_K/model.zip), --report with
        # the three seeds' plays and --baseline the _rule95shipped53_ ones (learned_caution_rule109)
        # rule 110: python experiments/train_estimator.py --policy cof_gym/agents/policies/interrogator
        # --out runs/estimator_encoder --climbs env=3000 procedural=3000 env_encoder=3000 procedural_encoder=3000;
        # validation_plays.py rule110EL --estimators runs/estimator_encoder/ensemble --set estimate_from=estimator
        # --encoder-lag (and rule110ELG with estimate_from=guard_estimator_pooled), rule95shipped53 and --hand-built
        # with --encoder-lag-only; frontier.py $(P rule95shipped53) $(P rule110EL) $(P rule110ELG) --shipped
        # $(P rule95shipped53) --references ... --rows (frontier_rule110_validation) and the same on the
        # _encoder_lag_s records (frontier_rule110_encoder_lag); rule_check.py on the four pairs --errors --error-grid
        # family --returns --more-runaways 1440 --same-climbs (rule_check_rule110C_i) and on the encoder_lag_s pair
        # --gain --errors --error-grid family --returns --more-runaways 360 (rule_check_rule110C_ii)
        # rule 111: validation_plays.py rule111ELG --estimators runs/estimator_encoder/ensemble --set
        # estimate_from=guard_estimator_pooled --confirmation confirmation36 torque_confirmation17
        # extremes_confirmation8 --encoder-lag, the same for rule111shipped and --hand-built; frontier.py over the
        # five plays joined by + with --rows (frontier_rule111) and on the _confirmation36_encoder_lag_s records
        # (frontier_rule111_encoder_lag); rule_check.py with the five pairs --gain --errors --error-grid family
        # --returns --more-runaways 2352 --same-climbs (rule_check_rule111) and the lag's pair with
        # --more-runaways 360 (rule_check_rule111_encoder_lag)
        # rule 112: experiments/rules/rule112.sh (train_interrogator.py --out runs/interrogator_encoder --climbs
        # torque_wide=8000 torque_wide_encoder=8000 --guard-climbs torque_wide=8000 procedural_torque_wide=8000
        # torque_wide_encoder=8000 procedural_torque_wide_encoder=8000 --fit-only; validation_plays.py rule112LF --run
        # runs/interrogator_encoder/ensemble --guards cof_gym/agents/policies/interrogator/guard_0
        # runs/interrogator_encoder/guard/ensemble --encoder-lag); frontier.py $(P rule95shipped53) $(P rule112LF)
        # --shipped $(P rule95shipped53) --references ... --rows (frontier_rule112_validation) and the same on the
        # _encoder_lag_s records (frontier_rule112_encoder_lag); rule_check.py on the four pairs --errors --error-grid
        # family --returns --more-runaways 1440 (rule_check_rule112LF_i) and on the encoder_lag_s pair --gain --errors
        # --error-grid family --returns --more-runaways 360 (rule_check_rule112LF_ii)
        # rule 113: experiments/rules/confirm113.sh (validation_plays.py rule113LF --run
        # runs/interrogator_encoder/ensemble --guards cof_gym/agents/policies/interrogator/guard_0
        # runs/interrogator_encoder/guard/ensemble --confirmation confirmation37 torque_confirmation18
        # extremes_confirmation9 --encoder-lag, the same for rule113shipped and --hand-built); frontier.py over the five
        # plays joined by + with --rows (frontier_rule113) and on the _confirmation37_encoder_lag_s records
        # (frontier_rule113_encoder_lag); rule_check.py with the five pairs --gain --errors --error-grid family
        # --returns --more-runaways 2352 (rule_check_rule113) and the lag's pair with --more-runaways 360
        # (rule_check_rule113_encoder_lag)
        # headroom_bias_rule113: python experiments/headroom_bias.py as its docstring gives it
        # rule 114: experiments/rules/rule114.sh (validation_plays.py rule114LFf --run
        # runs/interrogator_encoder/ensemble --encoder-lag); frontier.py and rule_check.py as for rule 112 with
        # rule114LFf, rule_check.py with --gain (frontier_rule114_validation, frontier_rule114_encoder_lag,
        # rule_check_rule114LFf_validation, rule_check_rule114LFf_encoder_lag)
        # rule 114's confirmation: experiments/rules/confirm114.sh (validation_plays.py rule114LFf --run
        # runs/interrogator_encoder/ensemble, rule114shipped and --hand-built, each --confirmation confirmation38
        # torque_confirmation19 extremes_confirmation10 --encoder-lag); frontier.py and rule_check.py as for rule 113
        # (frontier_rule114_confirmation, rule_check_rule114_confirmation, frontier_rule114_confirmation_encoder_lag,
        # rule_check_rule114_confirmation_encoder_lag)
        # rule 115: experiments/rules/rule115.sh (the union directories runs/union115/filter and runs/union115/guard_1,
        # copies of the shipped and LF's member files; validation_plays.py rule115U --run runs/union115/filter --guards
        # cof_gym/agents/policies/interrogator/guard_0 runs/union115/guard_1 --encoder-lag, then the same with
        # --confirmation confirmation37 torque_confirmation18 extremes_confirmation9 and with --confirmation
        # confirmation38 torque_confirmation19 extremes_confirmation10); frontier.py and rule_check.py as for rule 114
        # with rule115U (frontier_rule115_validation, frontier_rule115_encoder_lag, rule_check_rule115U_validation,
        # rule_check_rule115U_encoder_lag); rule_check.py with the ten pairs of the spent sets (rule113shipped's and
        # rule114shipped's records against rule115U's) --gain (rule_check_rule115U_spent)
        # rule 116: experiments/rules/rule116.sh (validation_plays.py rule116UsK with rule 115's --run and --guards,
        # --set spread_caution=K --encoder-lag, K = 1, 2); frontier.py over both candidates
        # (frontier_rule116_validation, frontier_rule116_encoder_lag) and rule_check.py as for rule 115
        # (rule_check_rule116UsK_validation, rule_check_rule116UsK_encoder_lag)
        # rule 117: experiments/rules/rule117.sh (the same with rule117UsK, K = 025, 05 for --set spread_caution=0.25,
        # 0.5); frontier.py and rule_check.py as for rule 116 (frontier_rule117_validation,
        # frontier_rule117_encoder_lag, rule_check_rule117UsK_validation, rule_check_rule117UsK_encoder_lag)
        # rule 118: experiments/rules/rule118.sh (validation_plays.py rule118U2 --run runs/union115/filter
        # --encoder-lag); frontier.py and rule_check.py as for rule 115 (frontier_rule118_validation,
        # frontier_rule118_encoder_lag, rule_check_rule118U2_validation, rule_check_rule118U2_encoder_lag)
        # rule 119: experiments/rules/rule119.sh (validation_plays.py rule119U2 --run runs/union115/filter with
        # --confirmation confirmation37 torque_confirmation18 extremes_confirmation9 and with --confirmation
        # confirmation38 torque_confirmation19 extremes_confirmation10); rule_check.py with the ten pairs as for rule
        # 115's (iii) (rule_check_rule119U2_spent)
        # headroom_bias_rule119: headroom_bias.py as its docstring gives it, with U=runs/union115/filter after LF and
        # guard_U=runs/union115/guard_1 after guard_LF, without guard_0, --out out/headroom_bias_rule119.md
        # rule 120: experiments/rules/collect_three.sh (the noisy collections), experiments/rules/rule120.sh (T's fit),
        # experiments/rules/rule120_plays.sh (TU's directories; validation_plays.py rule120T --run
        # runs/interrogator_three/ensemble --guards cof_gym/agents/policies/interrogator/guard_0
        # runs/interrogator_three/guard/ensemble --encoder-lag and rule120TU with runs/union120's); frontier.py and
        # rule_check.py as for rule 116 (frontier_rule120_validation, frontier_rule120_encoder_lag,
        # rule_check_rule120K_validation, rule_check_rule120K_encoder_lag, K = T, TU); TU's (iii): validation_plays.py
        # rule120TU --run runs/union120/filter --guards guard_0 runs/union120/guard_1 with --confirmation confirmation37
        # torque_confirmation18 extremes_confirmation9 and with --confirmation confirmation38 torque_confirmation19
        # extremes_confirmation10; rule_check.py with the ten pairs as for rule 119, --gain --discordant
        # (rule_check_rule120TU_spent)
        # rule 121: experiments/rules/rule121.sh (validation_plays.py rule121TU2 --run runs/union120/filter
        # --encoder-lag; rule121TU3 the same with --guards guard_0 guard_1 runs/interrogator_three/guard/ensemble);
        # frontier.py and rule_check.py as for rule 120 (frontier_rule121_validation, frontier_rule121_encoder_lag,
        # rule_check_rule121K_validation, rule_check_rule121K_encoder_lag, K = TU2, TU3)
        # rule 122: experiments/rules/rule122.sh (validation_plays.py rule122TUg --run runs/union120/filter
        # --encoder-lag --guards guard_0 runs/union120/guard_1 guard_1); frontier.py with rule120TU beside rule122TUg
        # and rule_check.py as for
        # rule 121 with --discordant (frontier_rule122_validation, frontier_rule122_encoder_lag,
        # rule_check_rule122TUg_validation, rule_check_rule122TUg_encoder_lag)
        # headroom_bias_rule122: headroom_bias.py --networks shipped=cof_gym/agents/policies/interrogator
        # T=runs/interrogator_three/ensemble TU=runs/union120/filter guard_1=cof_gym/agents/policies/interrogator/guard_1
        # guard_T=runs/interrogator_three/guard/ensemble guard_TU=runs/union120/guard_1 --climbs
        # runs/interrogator_three/climbs_{torque_wide,noisy_torque_wide,procedural_torque_wide,
        # procedural_noisy_torque_wide}.npz --out out/headroom_bias_rule122.md
        # rule 123: experiments/rules/rule123.sh; frontier.py with rule120TU, rule123TUk and rule123TUkg and rule_check.py
        # as for rule 122 (frontier_rule123_validation, frontier_rule123_encoder_lag, rule_check_rule123K_validation,
        # rule_check_rule123K_encoder_lag, K = TUk, TUkg); TUkg's (iii): experiments/rules/rule123_spent.sh rule123TUkg
        # 0.089, rule_check.py with the ten pairs as for rule 120's TU, --gain --discordant (rule_check_rule123TUkg_spent)
        # rule 123's confirmation: experiments/rules/confirm123.sh rule123TUkg 0.089; frontier.py over the five plays
        # joined by + with --rows against rule123shipped with the hand-built agents' references
        # (frontier_rule123_confirmation) and on the _confirmation39_encoder_lag_s records
        # (frontier_rule123_confirmation_encoder_lag); rule_check.py with the five pairs --gain --errors --error-grid
        # family --returns --more-runaways 2352 --discordant (rule_check_rule123_confirmation) and the lag's pair with
        # --errors --error-grid family --returns --more-runaways 360 (rule_check_rule123_confirmation_encoder_lag)
        # rule 124: experiments/rules/rule124.sh; frontier.py with rule123TUkg, rule124TUke and rule124TUkge and
        # rule_check.py as for rule 123 (frontier_rule124_validation, frontier_rule124_encoder_lag,
        # rule_check_rule124K_validation, rule_check_rule124K_encoder_lag, K = TUke, TUkge); TUkge's (iii):
        # experiments/rules/rule124_spent.sh rule124TUkge 0.089 0.70, rule_check.py with the ten pairs as for rule 123's
        # TUkg, --gain --discordant (rule_check_rule124TUkge_spent)
        # rule 125: rule_check.py with rule 123's TUk records against rule95shipped53, the four pairs --gain --errors
        # --error-grid family --returns --family-wise --more-runaways 1440 --discordant
        # (rule_check_rule125TUk_validation), the lagged pair the same with --more-runaways 360
        # (rule_check_rule125TUk_encoder_lag); (iii):
        # experiments/rules/rule123_spent.sh rule125TUk 0.086, rule_check.py with the ten pairs as for rule 124's TUkge,
        # --gain --sign-test --more-runaways 3840 --discordant (rule_check_rule125TUk_spent)
        # rule 125's confirmation: experiments/rules/confirm125.sh; frontier.py over the five plays joined by + with --rows
        # against rule125shipped with the hand-built agents' references (frontier_rule125_confirmation) and on the
        # _confirmation40_encoder_lag_s records (frontier_rule125_confirmation_encoder_lag); rule_check.py with the five
        # pairs --gain --sign-test --errors --error-grid family --returns --family-wise --more-runaways 2352
        # --discordant (rule_check_rule125_confirmation) and the lag's pair with --errors --error-grid family --returns
        # --family-wise --more-runaways 360 --discordant (rule_check_rule125_confirmation_encoder_lag)
        # rule 126: experiments/rules/rule126.sh; frontier.py with rule123TUk and rule126TUw as for rule 123
        # (frontier_rule126_validation, frontier_rule126_encoder_lag); rule_check.py as for rule 125's TUk
        # (rule_check_rule126TUw_validation, rule_check_rule126TUw_encoder_lag, rule_check_rule126TUw_spent)
        # rule 127: experiments/rules/rule127.sh (G's fit, runs/gate127, its five validation plays and the shipped
        # agent's, rule_check_rule127G_validation and rule_check_rule127G_encoder_lag), the hand-built agents'
        # (validation_plays.py --hand-built --encoder-lag); frontier.py $(P rule95shipped53) $(P rule127G)
        # --references ... --shipped $(P rule95shipped53) --rows (frontier_rule127_validation) and the same on the
        # _encoder_lag_s records (frontier_rule127_encoder_lag)
        # rule 128: experiments/rules/rule128.sh (rule_check_rule128G2.5_encoder_lag, rule_check_rule128G3_encoder_lag);
        # frontier.py on the _encoder_lag_s records of rule95shipped53, rule127G, rule128G2.5 and rule128G3 with the
        # hand-built agents' as references, --shipped rule95shipped53's, --rows (frontier_rule128_encoder_lag)
        # rule 129: experiments/rules/rule128.sh 2.25 129 (rule_check_rule129G2.25_encoder_lag,
        # rule_check_rule129G2.25_validation); frontier.py as for rule 128 with rule129G2.25 in place of rule128G3
        # (frontier_rule129_encoder_lag); its confirmation: experiments/rules/confirm129.sh
        # (frontier_rule129_confirmation, frontier_rule129_confirmation_encoder_lag, rule_check_rule129_confirmation,
        # rule_check_rule129_confirmation_encoder_lag)
        # rule 130: experiments/rules/confirm130.sh (rule_check_rule130_confirmation,
        # rule_check_rule130_confirmation_encoder_lag, rule_check_rule130_confirmation_encoder_lags)
        # rule 131: experiments/rules/confirm131.sh (rule_check_rule131_confirmation,
        # rule_check_rule131_confirmation_encoder_lags, rule_check_rule131_confirmation_encoder_lag30)
        # rule 132: experiments/rules/confirm132.sh (rule_check_rule132_confirmation_encoder_lags,
        # rule_check_rule132_confirmation_encoder_lag30, rule_check_rule132_confirmation)
        # rule 133: experiments/rules/confirm133.sh (rule_check_rule133_confirmation_encoder_lags,
        # rule_check_rule133_confirmation_encoder_lag30, rule_check_rule133_confirmation)
        # rule 134: experiments/rules/rule134.sh qualify (rule_check_rule134_slow_drive, rule_check_rule134_extremes,
        # rule_check_rule134_draws)
        # rule 135: experiments/rules/rule135.sh fit, then qualify (rule_check_rule135_validation,
        # rule_check_rule135_extremes), and the climbs it played by their curves' peak creepage:
    python experiments/peak_creepage_records.py --suite experiments/suites/v2_extremes_confirmation17_grid.json \
        --records out/records_rule135shipped_extremes_confirmation17.json \
        out/records_rule135F_extremes_confirmation17.json --out out/peak_creepage_rule135.md
        # rule 136: experiments/rules/rule136.sh qualify (rule_check_rule136_validation, rule_check_rule136_extremes)
        # rule 137: experiments/rules/rule137.sh qualify (rule_check_rule137_validation, rule_check_rule137_extremes)
        # and spent (rule_check_rule137_spent)
    python experiments/peak_creepage_records.py --suite experiments/suites/v2_extremes_confirmation17_grid.json \
        --records out/records_rule136G_extremes_confirmation17.json \
        out/records_rule137H_extremes_confirmation17.json --out out/peak_creepage_rule137.md
        # rule 138: experiments/rules/rule138.sh qualify a25 and qualify a50 (rule_check_rule138a25_validation,
        # rule_check_rule138a25_extremes, rule_check_rule138a50_validation, rule_check_rule138a50_extremes), then
        # explore (frontier_rule138, rule_check_x138a0c2)
        # rule 139: experiments/rules/rule139.sh qualify (rule_check_rule139_validation, rule_check_rule139_extremes)
        # rule 140: experiments/rules/rule140.sh fit, then qualify (rule_check_rule140_validation,
        # rule_check_rule140_extremes), and the climbs it played by their curves' peak creepage:
    python experiments/peak_creepage_records.py --suite experiments/suites/v2_extremes_confirmation17_grid.json \
        --records out/records_rule135shipped_extremes_confirmation17.json \
        out/records_rule140FR_extremes_confirmation17.json --out out/peak_creepage_rule140.md
        # rule 141: experiments/rules/rule141.sh fit, then qualify (rule_check_rule141_validation,
        # rule_check_rule141_extremes)
        # rule 142: experiments/rules/rule142.sh qualify (rule_check_rule142_validation, rule_check_rule142_extremes)
        # rule 143: experiments/rules/rule143.sh fit, then qualify (rule_check_rule143_validation,
        # rule_check_rule143_extremes)
    python experiments/select_model_based.py --out out/select_model_based.json   # model-based-zeroed-knee (session 74)
    python -m rl_zoo3.train --algo sac --env CofGym/TorqueInterrogation-v2 --gym-packages cof_gym \
        --conf-file cof_gym/agents/hyperparams/sac.yml -n 50000 --eval-freq -1 --seed 0 --log-folder runs/zoo_ref \
        --device cpu --vec-env subproc   # session 75, and the same with --algo ppo_lstm, ppo_lstm.yml, -n 100000; then
    cof-gym evaluate --agents interrogator,sb3:runs/zoo_ref/sac/CofGym-TorqueInterrogation-v2_1,\
sb3:runs/zoo_ref/ppo_lstm/CofGym-TorqueInterrogation-v2_1 --out out/evaluate-zoo-reference   # (block zoo_reference)
    python experiments/own_window_fit.py --episodes 200 --out out/own_window_fit.md   # session 74, information
    python experiments/shadow_reading.py --episodes 100 --out out/shadow_reading.md   # session 74, information, and
    python experiments/shadow_reading.py --agent interrogator --episodes 100 --out out/shadow_reading_interrogator.md
    python experiments/indistinguishable_peaks.py --counter-torque --agents staircase-zeroed,model-based-zeroed,\
model-based-zeroed-knee --out out/indistinguishable_peaks_zeroed.md   # session 81, information (94 s)
        # sessions 73-74: the hand-built agents, the three reading the zeroed creepage among them, on the four
        # validation plays (scripted_plays.py with A="staircase-zeroed model-based-zeroed model-based-zeroed-knee
        # phase-rule robust-model staircase model-based", as above), the shipped agent's (validation_plays.py
        # rule135shipped), then:
    python experiments/frontier.py $(P rule135shipped) --references $(for a in $A; do P $a; done) \
        --shipped $(P rule135shipped) --out out/frontier_zeroed.md --figure docs/interrogator_frontier_zeroed.png
        # session 70's exploration: experiments/rules/relative_shift.sh (crest_tradeoff_relative_shift_validation,
        # crest_tradeoff_relative_shift_confirmation43, crest_tradeoff_relative_shift_validation_noise)
    python experiments/encoder_lag_reading.py --sharp runs/interrogator_three/climbs_torque_wide.npz \
        runs/interrogator_three/climbs_procedural_torque_wide.npz \
        --lagged runs/interrogator_three/climbs_torque_wide_encoder.npz \
        runs/interrogator_three/climbs_procedural_torque_wide_encoder.npz --out out/encoder_lag_reading.md  # session 64
    python experiments/train_estimator.py --out runs/colour --collect-only \
        --climbs env=600 env_encoder=600 procedural=600 procedural_encoder=600   # session 65, 549 s; then
    python experiments/noise_colour_reading.py runs/colour/onpolicy_env_*.npz runs/colour/onpolicy_procedural_*.npz \
        --out out/noise_colour_reading.md
    python experiments/runaways_by_option.py out/records_shipped_validation_torque_session48.json \
        out/records_rule78M_validation_torque.json out/records_rule79P_validation_torque.json \
        out/records_rule80Q_validation_torque.json out/records_swap79PF_validation_torque.json --grids validation_torque \
        --option torque_gain_error --edges 0.05 0.1 --absolute --out out/runaways_by_torque_gain_session49.md
    python experiments/torque_balance.py   # session 46: the first window's balance on the selection data; and
    python experiments/torque_balance.py --suites experiments/suites/v2_heldout_grid.json \
        experiments/suites/v2_heldout{2,3,4,5,6,7}_grid.json --out out/torque_balance_heldout.md
    python experiments/readme_results.py

Each block sits between ``<!-- results:NAME:begin -->`` and ``<!-- results:NAME:end -->`` in one of
:data:`DOCUMENTS`;
a block whose source file is missing is left as it is (and reported). Two blocks are computed from the
evaluate summaries (:data:`GENERATED`): the learned agent's targets and the held-out overview.
"""

from __future__ import annotations

import csv
import json
import re
import shutil
import sys
from pathlib import Path

import numpy as np

from cof_gym.agents import registry
from cof_gym.commands.args import Parser
from cof_gym.commands.evaluate_stats import PEAK_CREEPAGE_BANDS, paired_differences, peak_creepage_band
from cof_gym.commands.evaluate_tables import ci_text

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_grids import v2_heldout_grids  # noqa: E402
from selection import TARGET_MEDIAN_PCT, TARGET_P90_PCT, TARGET_SLIPS_PER_100, target_rows  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCUMENTS = (README, ROOT / "docs" / "results.md", ROOT / "docs" / "interrogator.md")  # where blocks may sit
# the v2 held-out grids: README block (the grid's name without "_grid") -> (label, cof-gym evaluate --out)
HELDOUT_RUNS = {name.removesuffix("_grid"): (label, ROOT / "out" / f"evaluate-{name.removesuffix('_grid').replace('_', '-')}")
                for name, label in v2_heldout_grids().items()}
PAPER_RUN = ROOT / "out" / "evaluate-paper"  # cof-gym evaluate --suite paper --episodes 5 (its default --out)
SOURCES = {
    "default": ROOT / "out" / "evaluate" / "summary.md",
    "v2_no_errors": ROOT / "out" / "evaluate-v2-no-errors" / "summary.md",
    "v2_stress_tables": ROOT / "out" / "evaluate-v2-stress-tables" / "summary.md",
    "v2_extremes": ROOT / "out" / "evaluate-v2-extremes" / "summary.md",
    "v2_encoder_lag": ROOT / "out" / "evaluate-v2-encoder-lag" / "summary.md",
    "v2_ar1_default": ROOT / "out" / "evaluate-ar1" / "summary.md",
    "v2_track_ore_low": ROOT / "out" / "evaluate-v2-track-ore-low" / "summary.md",
    "v2_track_ore_high": ROOT / "out" / "evaluate-v2-track-ore-high" / "summary.md",
    "v2_encoder_pulses": ROOT / "out" / "evaluate-v2-encoder-pulses" / "summary.md",
    "v2_encoder_runout": ROOT / "out" / "evaluate-v2-encoder-runout" / "summary.md",
    "v2_encoder_runout_rotation": ROOT / "out" / "evaluate-v2-encoder-runout-rotation" / "summary.md",
    "v2_lock_in_rotation": ROOT / "out" / "evaluate-v2-lock-in-rotation" / "summary.md",
    "v2_rotation_clear": ROOT / "out" / "evaluate-v2-rotation-clear" / "summary.md",
    "v2_rotation_clear_runout": ROOT / "out" / "evaluate-v2-rotation-clear-runout" / "summary.md",
    "in_service": ROOT / "out" / "evaluate-in-service" / "summary.md",
    "in_service_variants": ROOT / "out" / "evaluate-in-service-variants" / "summary.md",
    "in_service_smooth": ROOT / "out" / "evaluate-in-service-smooth" / "summary.md",
    "in_service_heldout": ROOT / "out" / "evaluate-in-service-heldout" / "summary.md",
    # the learned interrogator fitted on task v3 (session 87: train_interrogator.py --env; shipped as
    # interrogator-in-service by rule 144, session 88) beside the agents it is paired with
    "in_service_learned": ROOT / "out" / "evaluate-in-service-learned" / "summary.md",
    "in_service_heldout_learned": ROOT / "out" / "evaluate-in-service-heldout-learned" / "summary.md",
    "v2_learned_v3": ROOT / "out" / "evaluate-v2-learned-v3" / "summary.md",
    "interrogator_in_service_seeds": ROOT / "runs" / "interrogator_in_service" / "report.md",
    # rule 144's candidate B, the recipe's later steps on v3 (session 88; not shipped)
    "interrogator_in_service_guarded_seeds": ROOT / "runs" / "interrogator_in_service_guarded" / "report.md",
    "track_lag_spread": ROOT / "out" / "track_lag_spread.md",  # experiments/track_lag_spread.py --out
    "select_phase_rule_in_service": ROOT / "out" / "select_phase_rule_in_service.md",
    "select_phase_rule_in_service_ar1": ROOT / "out" / "select_phase_rule_in_service_ar1.md",
    "v2_paper": PAPER_RUN / "summary.md",
    **{block: out / "summary.md" for block, (_, out) in HELDOUT_RUNS.items()},
    "v1_default": ROOT / "out" / "evaluate-v1" / "summary.md",
    "zoo_reference": ROOT / "out" / "evaluate-zoo-reference" / "summary.md",  # off-the-shelf RL from scratch
    "bench": ROOT / "out" / "bench.md",
    "heldout": ROOT / "out" / "evaluate-heldout" / "summary.md",
    "ppo_seeds": ROOT / "out" / "ppo_seeds" / "report.md",
    "interrogator_seeds": ROOT / "runs" / "interrogator_wide_balance" / "report.md",  # the recipe's run (rule 74)
    "interrogator_seeds_shipped": ROOT / "runs" / "interrogator_shipped" / "report.md",
    # experiments/crest_tradeoff.py, learning_curve.py and lag_near_peak.py: out/NAME.md for the block NAME
    **{name: ROOT / "out" / f"{name}.md" for name in (
        "crest_tradeoff",
        "crest_tradeoff_cm",
        "crest_tradeoff_spread",
        "crest_tradeoff_guard",
        "crest_tradeoff_stops",
        "learning_curve",
        "crest_tradeoff_data",
        "crest_tradeoff_own",
        "crest_tradeoff_data_guard",
        "crest_tradeoff_own_guard",
        "crest_tradeoff_procguard",
        "crest_tradeoff_mixguard",
        "crest_tradeoff_crest",
        "crest_tradeoff_crestnet",
        "crest_tradeoff_crept",
        "crest_tradeoff_shipped_stops",
        "crest_tradeoff_creep_steps",
        "crest_tradeoff_confirmation",
        "crest_tradeoff_confirmation_guard",
        "crest_tradeoff_guarded_cautions",
        "crest_tradeoff_steepguard",
        "crest_tradeoff_approach",
        "crest_tradeoff_max_step",
        "amplitude_probe_held",
        "amplitude_probe_held_ct",
        "amplitude_probe_staircase",
        "amplitude_probe_staircase_ct",
        "crest_tradeoff_cm_guard",
        "amplitude_probe_held85",
        "crest_tradeoff_estimate",
        "crest_tradeoff_estimate_headroom",
        "crest_tradeoff_estimate_confirmation2",
        "crest_tradeoff_estimator",
        "crest_tradeoff_estimator_family",
        "crest_tradeoff_estimator_headroom",
        "crest_tradeoff_estimator_confirmation3",
        "crest_tradeoff_release",
        "crest_tradeoff_release_confirmation4",
        "crest_tradeoff_approach_until",
        "crest_tradeoff_crest_floor",
        "crest_tradeoff_crest_floor_confirmation5",
        "crest_tradeoff_cycle_crest",
        "crest_tradeoff_runaway",
        "crest_tradeoff_runaway_confirmation6",
        "crest_tradeoff_pace",
        "crest_tradeoff_frequency",
        "crest_tradeoff_knee",
        "crest_tradeoff_ceiling",
        "crest_tradeoff_ceiling_confirmation7",
        "crest_tradeoff_ceiling_stop",
        "crest_tradeoff_median_estimator",
        "crest_tradeoff_mean_estimator",
        "crest_tradeoff_median_at_headroom",
        "crest_tradeoff_mixed_median_at_headroom",
        "crest_tradeoff_mixed_median_at_headroom_confirmation8",
        "paired_rule33_validation",
        "paired_rule33_confirmation8",
        "crest_tradeoff_laplace_filter",
        "crest_tradeoff_speed_scaled",
        "indistinguishable_peaks",
        "feature_block_nll",
        "crest_tradeoff_climb_fit",
        "crest_tradeoff_climb_fit_estimator",
        "crest_tradeoff_filter_onpolicy",
        "crest_tradeoff_filter_onpolicy_confirmation9",
        "paired_rule37_confirmation9",
        "crest_tradeoff_filter_onpolicy_mixed",
        "crest_tradeoff_dagger1",
        "crest_tradeoff_guard_onpolicy",
        "paired_rule40_validation",
        "crest_tradeoff_guard_onpolicy_env",
        "crest_tradeoff_shipped_confirmation10",
        "crest_tradeoff_guard_onpolicy_env_confirmation10",
        "paired_rule41_confirmation10",
        "crest_tradeoff_rule42_both_guards",
        "crest_tradeoff_rule42_A",
        "crest_tradeoff_rule42_B",
        "crest_tradeoff_shipped_confirmation11",
        "crest_tradeoff_rule42_confirmation11",
        "paired_rule42_confirmation11",
        "crest_tradeoff_shipped_validation_session30",
        "crest_tradeoff_rule43",
        "paired_rule43_validation",
        "crest_tradeoff_rule44",
        "paired_rule44_validation",
        "crest_tradeoff_rule44_confirmation12",
        "paired_rule44_confirmation12",
        "crest_tradeoff_rule45",
        "paired_rule45_validation",
        "crest_tradeoff_shipped_confirmation13",
        "crest_tradeoff_rule45_confirmation13",
        "paired_rule45_confirmation13",
        "crest_tradeoff_shipped_validation_session31",
        "crest_tradeoff_rule46",
        "paired_rule46_validation",
        "crest_tradeoff_rule46_confirmation14",
        "paired_rule46_confirmation14",
        "crest_tradeoff_rule47",
        "paired_rule47_validation",
        "crest_tradeoff_shipped_validation_session32",
        "crest_tradeoff_rule48",
        "crest_tradeoff_rule48_noise3",
        "paired_rule48_validation",
        "paired_rule48_validation_noise3",
        "crest_tradeoff_rule49",
        "crest_tradeoff_rule49_noise3",
        "paired_rule49_validation",
        "paired_rule49_validation_noise3",
        "crest_tradeoff_rule49_confirmation15",
        "crest_tradeoff_rule49_confirmation15_noise3",
        "paired_rule49_confirmation15",
        "paired_rule49_confirmation15_noise3",
        "crest_tradeoff_rule50_confirmation16",
        "crest_tradeoff_rule50_confirmation16_noise3",
        "paired_rule50_confirmation16",
        "paired_rule50_confirmation16_noise3",
        "crest_tradeoff_shipped_validation_session33",
        "crest_tradeoff_shipped_validation_session33_noise3",
        "crest_tradeoff_rule51A_validation",
        "paired_rule51A_validation",
        "crest_tradeoff_rule51A_validation_noise3",
        "paired_rule51A_validation_noise3",
        "crest_tradeoff_rule51B_validation",
        "paired_rule51B_validation",
        "crest_tradeoff_rule51B_validation_noise3",
        "paired_rule51B_validation_noise3",
        "paired_rule51A_validation_lag01",
        "paired_rule51B_validation_lag01",
        "crest_tradeoff_noise_pace_session34",
        "crest_tradeoff_noise_pace_session34_noise3",
        "noise_reading",
        "crest_tradeoff_rule52_validation_noise3",
        "paired_rule52_validation_noise3",
        "crest_tradeoff_rule53_validation_noise3",
        "paired_rule53_validation_noise3",
        "crest_tradeoff_rule53_confirmation17_noise3",
        "paired_rule53_confirmation17_noise3",
        "crest_tradeoff_rule53_confirmation17",
        "crest_tradeoff_rule54_validation_noise2",
        "paired_rule54_validation_noise2",
        "paired_rule54_validation_noise3",
        "paired_rule54_validation_lag01",
        "crest_tradeoff_rule55_validation_noise2",
        "paired_rule55_validation_noise2",
        "paired_rule55_validation_noise3",
        "knee_twins",
        "knee_twins_125",
        "estimate_interval",
        "crest_tradeoff_rule56_validation",
        "paired_rule56_validation",
        "paired_rule56_validation_noise2",
        "crest_tradeoff_rule57_validation",
        "paired_rule57_validation",
        "paired_rule57_validation_noise2",
        "crest_tradeoff_rule58_validation",
        "crest_tradeoff_rule58_validation_noise2",
        "paired_rule58_validation",
        "paired_rule58_validation_noise2",
        "paired_rule59_validation",
        "paired_rule59_validation_noise2",
        "crest_tradeoff_rule59_confirmation18",
        "paired_rule59_confirmation18",
        "crest_tradeoff_rule60_validation",
        "paired_rule60_validation",
        "paired_rule60_validation_noise2",
        "crest_tradeoff_rule60_confirmation19",
        "paired_rule60_confirmation19",
        "crest_tradeoff_rule61_validation",
        "crest_tradeoff_rule62_validation",
        "crest_tradeoff_rule62_validation_lag01",
        "paired_rule62_validation",
        "paired_rule62_validation_lag01",
        "crest_tradeoff_rule63_validation",
        "crest_tradeoff_rule63_validation_lag01",
        "paired_rule63_validation",
        "paired_rule63_validation_lag01",
        "sensor_sensitivity", "sensor_sensitivity_gated", "sensor_sensitivity_zeroed",
        "crest_tradeoff_shipped_validation_session45",
        "crest_tradeoff_shipped_validation_session45_torque_low",
        "crest_tradeoff_shipped_validation_session45_torque_high",
        "crest_tradeoff_rule64B_validation",
        "crest_tradeoff_rule64B_validation_torque_low",
        "crest_tradeoff_rule64B_validation_torque_high",
        "crest_tradeoff_rule64C_validation",
        "crest_tradeoff_rule64C_validation_torque_low",
        "crest_tradeoff_rule64C_validation_torque_high",
        "crest_tradeoff_rule64D_validation",
        "crest_tradeoff_rule64D_validation_torque_low",
        "crest_tradeoff_rule64D_validation_torque_high",
        "paired_rule64_validation",
        "paired_rule64_validation_torque_low",
        "paired_rule64_validation_torque_high",
        "feature_block_nll_torque_free",
        "crest_tradeoff_rule65E_validation",
        "crest_tradeoff_rule65E_validation_torque_low",
        "crest_tradeoff_rule65E_validation_torque_high",
        "paired_rule65E_validation",
        "paired_rule65E_validation_torque_low",
        "paired_rule65E_validation_torque_high",
        "crest_tradeoff_shipped_validation_torque",
        "crest_tradeoff_rule64D_validation_torque",
        "crest_tradeoff_rule65E_validation_torque",
        "paired_validation_torque",
        "crest_tradeoff_shipped_rule66_confirmation20",
        "crest_tradeoff_rule66D_confirmation20",
        "paired_rule66_confirmation20",
        "crest_tradeoff_shipped_rule66_torque_confirmation",
        "crest_tradeoff_rule66D_torque_confirmation",
        "paired_rule66_torque_confirmation",
        "crest_tradeoff_rule67_validation",
        "paired_rule67_validation",
        "crest_tradeoff_rule67_validation_torque",
        "paired_rule67_validation_torque",
        "crest_tradeoff_rule68G_validation",
        "paired_rule68G_validation",
        "crest_tradeoff_rule68G_validation_torque",
        "paired_rule68G_validation_torque",
        "crest_tradeoff_rule68H_validation",
        "paired_rule68H_validation",
        "crest_tradeoff_rule68H_validation_torque",
        "paired_rule68H_validation_torque",
        *(f"{kind}_rule69{c}_{grids}" for c in "DH" for grids in ("validation", "validation_torque")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{name}_{grids}" for grids in ("confirmation21", "torque_confirmation2")
          for name in ("crest_tradeoff_shipped_rule69", "crest_tradeoff_rule69XH", "paired_rule69")),
        *(f"{kind}_rule70T_{grids}" for grids in ("validation", "validation_torque")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{name}_{grids}" for grids in ("confirmation22", "torque_confirmation3")
          for name in ("crest_tradeoff_shipped_rule70", "crest_tradeoff_rule70T", "paired_rule70")),
        *(f"{kind}_rule71_{grids}" for grids in ("validation", "validation_torque")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{name}_{grids}" for grids in ("confirmation23", "torque_confirmation4")
          for name in ("crest_tradeoff_shipped_rule71", "crest_tradeoff_rule71T65", "paired_rule71")),
        "torque_balance",
        "torque_balance_heldout",
        *(f"crest_tradeoff_shipped_{grids}_session47" for grids in ("validation", "validation_torque")),
        *(f"{kind}_rule{c}_{grids}" for c in ("72KF", "72K", "73WF", "73W")
          for grids in ("validation", "validation_torque") for kind in ("crest_tradeoff", "paired")),
        *(f"{name}_{grids}" for grids in ("confirmation24", "torque_confirmation5")
          for name in ("crest_tradeoff_shipped_rule73", "crest_tradeoff_rule73W", "paired_rule73")),
        *(f"{name}_{grids}" for grids in ("confirmation25", "torque_confirmation6")
          for name in ("crest_tradeoff_shipped_rule74", "crest_tradeoff_rule74W", "paired_rule74")),
        *(f"{name}_{tag}_session48" for tag in ("noise_level", "motor_lag_s")
          for name in ("crest_tradeoff_prev", "crest_tradeoff_shipped", "paired")),
        *(f"crest_tradeoff_shipped_{grids}_session48" for grids in ("validation", "validation_torque")),
        *(f"{kind}_rule75V_{grids}" for grids in ("validation", "validation_torque", "noise_level")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{kind}_rule76_{grids}" for grids in ("validation", "validation_torque") for kind in ("crest_tradeoff", "paired")),
        *(f"{kind}_rule77{c}_{grids}" for c in "NZ" for grids in ("validation", "validation_torque", "noise_level")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{kind}_rule{c}_{grids}"
          for c in ("78M", "79P", "80Q", "81R3", "81R4", "82R3a", "82R3b", "82R3c", "83A25", "83A50")
          for grids in ("validation", "validation_torque", "noise_level", "motor_lag_s")
          for kind in ("crest_tradeoff", "paired")),
        *(f"{name}_{play}"
          for play in ("confirmation26", "confirmation26_noise_level", "confirmation26_motor_lag_s",
                       "torque_confirmation7")
          for name in ("crest_tradeoff_shipped", "crest_tradeoff_rule84R3", "paired_rule84R3")),
        "rule_check_rule84_a", "rule_check_rule84_b",
        *(f"paired_rule85F_{play}"
          for play in ("validation", "validation_torque", "noise_level", "motor_lag_s", "confirmation27",
                       "confirmation27_noise_level", "confirmation27_motor_lag_s", "torque_confirmation8")),
        "rule_check_rule85_a", "rule_check_rule85_b",
        *(f"rule_check_rule86c{c}_selection" for c in ("2.25", "2.5", "2.75")),
        "rule_check_rule86_a", "rule_check_rule86_b",
        *(f"rule_check_rule87s{v}_selection" for v in ("1.0", "1.5")),
        "paired_rule88C_validation_extremes", "rule_check_rule88_a", "rule_check_rule88_b",
        *(f"crest_tradeoff_rule89K{c}_validation" for c in ("n", "0", "p")),
        "paired_rule89K0_validation_extremes",
        "frontier_validation", "frontier_rule90", "rule_check_rule90_b", "rule_check_rule90_c",
        "frontier_rule91_validation",
        *(f"rule_check_rule91P{c}_{k}" for c in ("2.25", "2.5") for k in ("b", "c")),
        "frontier_rule92_validation", *(f"rule_check_rule92{c}_c" for c in ("EF", "EF1", "EP", "EFP")),
        "frontier_rule93_validation", *(f"rule_check_rule93{c}_c" for c in ("GP", "GQ", "GPQ")),
        "frontier_rule93", "rule_check_rule93_c",
        "frontier_rule94_validation", *(f"rule_check_rule94{c}_c" for c in ("S10", "R30", "R45", "R60")),
        "frontier_rule94", "rule_check_rule94_c",
        "frontier_rule95_validation", *(f"rule_check_rule95{c}_c" for c in ("N05", "N1", "N2")),
        "frontier_rule95", "rule_check_rule95_c",
        "frontier_rule96_validation", *(f"rule_check_rule96{c}_c" for c in ("K10", "K15")),
        "frontier_explore97", "frontier_rule97_validation",
        *(f"rule_check_rule97{c}_c" for c in ("P20", "P175", "P15U20")),
        "frontier_rule98_validation", "rule_check_rule98A_c", "frontier_explore99", "frontier_explore99b",
        "frontier_rule99_validation", *(f"rule_check_rule99{c}_c" for c in ("E", "EG")), "frontier_explore100",
        "frontier_rule100_validation", "rule_check_rule100AFE_c",
        "frontier_rule101_validation", *(f"rule_check_rule101{c}_c" for c in ("A2", "A3")), "frontier_explore102",
        "rule_check_rule102EG_validation", "frontier_rule102", "rule_check_rule102",
        "frontier_rule103_validation", "rule_check_rule103S3_c",
        "learned_caution_rule104", "frontier_rule104_validation", "rule_check_rule104L0_c", "frontier_rule104",
        "rule_check_rule104", "frontier_rule105_validation", "rule_check_rule105L_c",
        "learned_caution_rule106", "frontier_rule106_validation", "rule_check_rule106L3_c",
        "frontier_rule107_validation", "rule_check_rule107E_c", "learned_caution_rule108",
        "learned_caution_rule109",
        "frontier_rule110_validation", "frontier_rule110_encoder_lag",
        *(f"rule_check_rule110{c}_{k}" for c in ("EL", "ELG") for k in ("i", "ii")),
        "frontier_rule111", "rule_check_rule111", "frontier_rule111_encoder_lag", "rule_check_rule111_encoder_lag",
        "frontier_rule112_validation", "frontier_rule112_encoder_lag",
        "rule_check_rule112LF_i", "rule_check_rule112LF_ii",
        "frontier_rule113", "rule_check_rule113", "frontier_rule113_encoder_lag", "rule_check_rule113_encoder_lag",
        "headroom_bias_rule113",
        "frontier_rule114_validation", "frontier_rule114_encoder_lag", "rule_check_rule114LFf_validation",
        "rule_check_rule114LFf_encoder_lag",
        "frontier_rule114_confirmation", "rule_check_rule114_confirmation", "frontier_rule114_confirmation_encoder_lag",
        "rule_check_rule114_confirmation_encoder_lag",
        "frontier_rule115_validation", "frontier_rule115_encoder_lag", "rule_check_rule115U_validation",
        "rule_check_rule115U_encoder_lag", "rule_check_rule115U_spent",
        "frontier_rule116_validation", "frontier_rule116_encoder_lag",
        *(f"rule_check_rule116Us{k}_{play}" for k in (1, 2) for play in ("validation", "encoder_lag")),
        "frontier_rule117_validation", "frontier_rule117_encoder_lag",
        *(f"rule_check_rule117Us{k}_{play}" for k in ("025", "05") for play in ("validation", "encoder_lag")),
        "frontier_rule118_validation", "frontier_rule118_encoder_lag", "rule_check_rule118U2_validation",
        "rule_check_rule118U2_encoder_lag", "rule_check_rule119U2_spent", "headroom_bias_rule119",
        "frontier_rule120_validation", "frontier_rule120_encoder_lag",
        *(f"rule_check_rule120{k}_{play}" for k in ("T", "TU") for play in ("validation", "encoder_lag")),
        "rule_check_rule120TU_spent", "frontier_rule121_validation", "frontier_rule121_encoder_lag",
        *(f"rule_check_rule121{k}_{play}" for k in ("TU2", "TU3") for play in ("validation", "encoder_lag")),
        "frontier_rule122_validation", "frontier_rule122_encoder_lag", "rule_check_rule122TUg_validation",
        "rule_check_rule122TUg_encoder_lag", "headroom_bias_rule122",
        "frontier_rule123_validation", "frontier_rule123_encoder_lag",
        *(f"rule_check_rule123{k}_{play}" for k in ("TUk", "TUkg") for play in ("validation", "encoder_lag")),
        "rule_check_rule123TUkg_spent", "frontier_rule123_confirmation", "rule_check_rule123_confirmation",
        "frontier_rule123_confirmation_encoder_lag", "rule_check_rule123_confirmation_encoder_lag",
        "frontier_rule124_validation", "frontier_rule124_encoder_lag",
        *(f"rule_check_rule124{k}_{play}" for k in ("TUke", "TUkge") for play in ("validation", "encoder_lag")),
        "rule_check_rule124TUkge_spent",
        *(f"rule_check_rule125TUk_{play}" for play in ("validation", "encoder_lag", "spent")),
        "frontier_rule125_confirmation", "frontier_rule125_confirmation_encoder_lag", "rule_check_rule125_confirmation",
        "rule_check_rule125_confirmation_encoder_lag",
        "frontier_rule126_validation", "frontier_rule126_encoder_lag",
        *(f"rule_check_rule126TUw_{play}" for play in ("validation", "encoder_lag", "spent")),
        "frontier_rule127_validation", "frontier_rule127_encoder_lag",
        *(f"rule_check_rule127G_{play}" for play in ("validation", "encoder_lag")),
        "frontier_rule128_encoder_lag", *(f"rule_check_rule128G{c}_encoder_lag" for c in ("2.5", "3")),
        "frontier_rule129_encoder_lag", *(f"rule_check_rule129G2.25_{play}" for play in ("encoder_lag", "validation")),
        "frontier_rule129_confirmation", "frontier_rule129_confirmation_encoder_lag", "rule_check_rule129_confirmation",
        "rule_check_rule129_confirmation_encoder_lag",
        *(f"rule_check_rule130_confirmation{play}" for play in ("", "_encoder_lag", "_encoder_lags")),
        *(f"rule_check_rule13{r}_confirmation{play}" for r in (1, 2, 3)
          for play in ("", "_encoder_lags", "_encoder_lag30")),
        *(f"rule_check_rule134_{check}" for check in ("slow_drive", "extremes", "draws")),
        *(f"rule_check_rule135_{check}" for check in ("validation", "extremes")), "peak_creepage_rule135",
        *(f"rule_check_rule13{r}_{check}" for r in (6, 7) for check in ("validation", "extremes")),
        "peak_creepage_rule137", "rule_check_rule137_spent",
        *(f"rule_check_rule138{c}_{check}" for c in ("a25", "a50") for check in ("validation", "extremes")),
        "frontier_rule138", "rule_check_x138a0c2",
        *(f"rule_check_rule139_{check}" for check in ("validation", "extremes")),
        *(f"rule_check_rule140_{check}" for check in ("validation", "extremes")), "peak_creepage_rule140",
        *(f"rule_check_rule141_{check}" for check in ("validation", "extremes")),
        "frontier_zeroed", *(f"rule_check_rule142_{check}" for check in ("validation", "extremes")),
        "select_model_based", "own_window_fit", "shadow_reading", "shadow_reading_interrogator",
        *(f"rule_check_rule143_{check}" for check in ("validation", "extremes")),
        *(f"crest_tradeoff_relative_shift_{play}" for play in ("validation", "confirmation43", "validation_noise")),
        "encoder_lag_reading", "noise_colour_reading",
        *(f"rule_check_rule89K{c}_{condition}" for c in ("n", "0", "p") for condition in ("i", "ii", "iii", "iv")),
        *(f"{kind}_swap79{c}_{grids}" for c in ("PF", "PG") for grids in ("validation_torque", "noise_level")
          for kind in ("crest_tradeoff", "paired")),
        "runaways_by_torque_gain_session49", "indistinguishable_peaks_zeroed",
    )},
}
LEARNED = "interrogator"  # the learned agent the issue's targets are about
# the learned interrogator fitted on task v3 (session 87: train_interrogator.py --env
# CofGym/TorqueInterrogationInService-v3; shipped as interrogator-in-service by rule 144, session 88), and every v2
# held-out grid played on v3 beside the agents of its in-service run (cof-gym evaluate --env, into
# out/evaluate-in-service-heldoutK-learned)
V3_LEARNED = "interrogator-in-service"
# the agents beside it in those runs that read no truth (the --agents of the docstring's commands, in that order)
IN_SERVICE_RIVALS = ("interrogator", "phase-rule-in-service", "staircase-zeroed", "model-based-zeroed")
IN_SERVICE_HELDOUT_RUNS = {name: (label, ROOT / "out" / f"evaluate-in-service-{name.removeprefix('v2_')}-learned")
                           for name, (label, _) in HELDOUT_RUNS.items()}
TARGET_SUITES = {"v2 default suite (`cof-gym evaluate`)": ROOT / "out" / "evaluate" / "summary.json",
                 **{f"{label} (`--suite experiments/suites/{block}_grid.json`)": out / "summary.json"
                    for block, (label, out) in HELDOUT_RUNS.items()}}


def body(path: Path) -> str:
    """The file without its level-1 title (the README's section says what it is)."""
    lines = path.read_text().strip().splitlines()
    lines = [f"*{line[3:]}*" if line.startswith("## ") else line for line in lines if not line.startswith("# ")]
    return "\n".join(lines).strip()


FIGURES = {  # figure of a run -> where the README shows it
    ROOT / "out" / "evaluate" / "error_vs_creepage_error.png": ROOT / "docs" / "evaluate_error_vs_creepage_error.png",
    ROOT / "out" / "evaluate" / "error_vs_peak_torque.png": ROOT / "docs" / "evaluate_error_vs_peak_torque.png",
    ROOT / "out" / "estimate_interval_in_flight.png": ROOT / "docs" / "estimate_interval_in_flight.png",
}


def _stat(summary: dict, agent: str, key: str) -> float:
    return float(summary[agent][key]["value"])


def _load(path: Path, learned: str) -> dict | None:
    """The evaluate summary at ``path``; None when it is missing or lacks the learned agent."""
    if not path.is_file():
        return None
    summary = json.loads(path.read_text())["summary"]
    return summary if learned in summary else None


def _best(summary: dict, learned: str, key: str) -> str:
    """The agent that does not read the truth (other than ``learned``) with the lowest ``key``."""
    others = [a for a, v in summary.items() if not v["oracle"] and a != learned]
    return min(others, key=lambda a: _stat(summary, a, key))


def _triple(median: float, p90: float, slips: float) -> str:
    """A table cell: median / P90 error (fractions, shown in %) / macro-slips."""
    return f"{100 * median:.1f} % / {100 * p90:.1f} % / {slips:.0f}"


def _cell(summary: dict, agent: str) -> str:
    return _triple(*(_stat(summary, agent, key) for key in ("median_error", "p90_error", "macro_slip_events")))


def target_checks(paths: dict[str, Path] = TARGET_SUITES,
                  learned: str = LEARNED) -> list[tuple[str, str, str, bool]] | None:
    """The learned agent's targets (median <= 3 %, P90 <= 8 %, <= 1 macro-slip per 100 episodes, better
    than every non-oracle agent on median and P90 with no more macro-slips than the best of them; the
    stretch: median <= 5 % with the estimate committed at <= 90 % of the true saturation torque, read as
    the mean peak torque of the episodes) as (suite, target, measured, met) rows, from the evaluate summaries; None
    when a summary is missing."""
    checks = []
    for label, path in paths.items():
        summary = _load(path, learned)
        if summary is None:
            return None
        n = summary[learned]["episodes"]
        med, p90 = 100 * _stat(summary, learned, "median_error"), 100 * _stat(summary, learned, "p90_error")
        slips = _stat(summary, learned, "macro_slip_events")
        peak = 100 * _stat(summary, learned, "peak_torque_fraction")
        best_med, best_p90 = _best(summary, learned, "median_error"), _best(summary, learned, "p90_error")
        fewest = _stat(summary, _best(summary, learned, "macro_slip_events"), "macro_slip_events")
        others = [(100 * _stat(summary, a, "median_error"), 100 * _stat(summary, a, "p90_error"),
                   _stat(summary, a, "macro_slip_events")) for a, v in summary.items() if not v["oracle"] and a != learned]
        met = target_rows(med, p90, slips, n, others)
        checks += [(label, *check) for check in (
            (f"median <= {TARGET_MEDIAN_PCT:g} %", f"{med:.1f} %", met[0]),
            (f"P90 <= {TARGET_P90_PCT:g} %", f"{p90:.1f} %", met[1]),
            (f"<= {TARGET_SLIPS_PER_100:g} macro-slip per 100 episodes", f"{slips:.0f} in {n}", met[2]),
            ("median below every non-oracle agent's", f"{med:.1f} % vs {best_med} "
             f"{100 * _stat(summary, best_med, 'median_error'):.1f} %", met[3]),
            ("P90 below every non-oracle agent's", f"{p90:.1f} % vs {best_p90} "
             f"{100 * _stat(summary, best_p90, 'p90_error'):.1f} %", met[4]),
            ("no more macro-slips than the best non-oracle agent", f"{slips:.0f} vs {fewest:.0f}", met[5]),
            ("stretch: median <= 5 % committed at <= 90 % of M_sat (mean peak torque)", f"{med:.1f} % at {peak:.1f} %",
             med <= 5.0 and peak <= 90.0),
        )]
    return checks


def targets(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """:func:`target_checks` as a table, each row marked met or not; None when a summary is missing."""
    checks = target_checks(paths, learned)
    if checks is None:
        return None
    rows = ["| suite | target | measured | met |", "|---|---|---|---|"]
    rows += [f"| {suite} | {t} | {m} | {'met' if ok else '**not met**'} |" for suite, t, m, ok in checks]
    return "\n".join(rows)


def _errors_and_returns(episodes_csv: Path) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every agent's relative errors and episode returns in ``episodes_csv`` (evaluate's), in episode order."""
    with open(episodes_csv, newline="") as f:
        rows = sorted(csv.DictReader(f), key=lambda r: int(r["episode"]))
    agents = dict.fromkeys(r["agent"] for r in rows)
    return {agent: tuple(np.array([float(r[key]) for r in rows if r["agent"] == agent])
                         for key in ("relative_error", "episode_return")) for agent in agents}


def paired_targets(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """Per suite, the learned agent against the agent with the lowest other median and the one with the lowest
    other P90 (the targets' comparisons), paired over the same episodes (``episodes.csv`` beside each summary;
    :func:`cof_gym.commands.evaluate_stats.paired_differences`, as ``cof-gym evaluate --paired`` computes it): the
    difference with its 95 % CI, and the share of episodes in which the learned agent's error is the lower; None when
    a summary or its episodes are missing."""
    rows = [f"| suite | lowest other median | median, {learned} - it [95 % CI] (points) | {learned}'s error the lower "
            f"[% of episodes, 95 % CI] | lowest other P90 | P90, {learned} - it [95 % CI] (points) |",
            "|---|---|---|---|---|---|"]
    for label, path in paths.items():
        summary, episodes = _load(path, learned), path.parent / "episodes.csv"
        if summary is None or not episodes.is_file():
            return None
        best_med, best_p90 = _best(summary, learned, "median_error"), _best(summary, learned, "p90_error")
        played = _errors_and_returns(episodes)
        error, episode_return = played[learned]
        against = {rival: paired_differences(played[rival][0], error, played[rival][1], episode_return)
                   for rival in {best_med, best_p90}}  # one bootstrap where one agent is both
        rows.append(f"| {label} | {best_med} | {ci_text(against[best_med]['median'])} | "
                    f"{ci_text(against[best_med]['lower_error'], 0, signed=False)} | {best_p90} | "
                    f"{ci_text(against[best_p90]['P90'])} |")
    return "\n".join(rows)


def rate_interval(events: int, trials: int, confidence: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper-Pearson) two-sided ``confidence`` interval of a rate seen as ``events`` in ``trials``
    (Clopper and Pearson 1934, Biometrika 26:404-413): beta quantiles, 0 below no event and 1 above all."""
    from scipy.stats import beta

    if not (0 <= events <= trials and trials > 0 and 0.0 < confidence < 1.0):
        raise ValueError(f"a rate needs 0 <= events <= trials, trials > 0 and a confidence in (0, 1); got {events} "
                         f"events in {trials} trials at {confidence}")
    tail = (1.0 - confidence) / 2.0
    low = 0.0 if events == 0 else float(beta.ppf(tail, events, trials - events + 1))
    high = 1.0 if events == trials else float(beta.ppf(1.0 - tail, events + 1, trials - events))
    return low, high


def slip_rates(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """Per suite, the learned agent's macro-slips as a rate per 100 episodes with its exact 95 % interval, against
    the target's 1 per 100: whether the suite shows the rate below it, above it, or cannot tell; None when a summary
    is missing."""
    rows = [f"| suite | {learned}: macro-slips (episodes) | per 100 episodes [95 % CI] | against <= "
            f"{TARGET_SLIPS_PER_100:g} per 100 |", "|---|---|---|---|"]
    for label, path in paths.items():
        summary = _load(path, learned)
        if summary is None:
            return None
        n, slips = summary[learned]["episodes"], int(_stat(summary, learned, "macro_slip_events"))
        low, high = (100.0 * v for v in rate_interval(slips, n))
        verdict = ("shown below" if high <= TARGET_SLIPS_PER_100 else "shown above" if low > TARGET_SLIPS_PER_100
                   else "cannot tell")
        rows.append(f"| {label} | {slips} ({n}) | {100.0 * slips / n:.1f} [{low:.1f}, {high:.1f}] | {verdict} |")
    return "\n".join(rows)


def targets_count(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """One line over :func:`target_checks`: how many rows are met, and of those missed how many are on the held-out
    grids (every suite but the first, the default suite); None when a summary is missing."""
    checks = target_checks(paths, learned)
    if checks is None:
        return None
    default = next(iter(paths))
    missed = [suite for suite, *_, ok in checks if not ok]
    on_grids = sum(suite != default for suite in missed)
    return (f"{len(checks) - len(missed)} of the {len(checks)} target rows are met; of the {len(missed)} it misses, "
            f"{on_grids} are on the held-out grids.")


def at_a_glance(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """Every agent that does not read the truth, the learned one first: median / P90 / macro-slips on the default
    suite (the first of ``paths``), and over the held-out grids (the others) its macro-slips in all their episodes and
    the lowest and highest of its medians, as the issue states them and with every macro-slip counted as a failed
    measurement (100 %); then the count of the learned agent's target rows met. None when a summary is missing."""
    summaries = [_load(path, learned) for path in paths.values()]
    if any(s is None for s in summaries):
        return None
    default, *grids = summaries
    agents = [learned] + [a for a, v in default.items() if not v["oracle"] and a != learned]
    episodes = sum(g[learned]["episodes"] for g in grids)
    rows = [f"| agent (no ground truth) | default suite: median / P90 / macro-slips ({default[learned]['episodes']}) | "
            f"{len(grids)} held-out grids: macro-slips ({episodes}) | held-out grids: median, lowest - highest | "
            "held-out grids: median with a macro-slip counted as 100 %, lowest - highest |",
            "|---|---|---|---|---|"]

    def spread(agent: str, key: str) -> str:
        """The lowest and highest of ``agent``'s ``key`` over the grids, in %."""
        values = [100 * _stat(g, agent, key) for g in grids]
        return f"{min(values):.1f} - {max(values):.1f} %"

    for agent in agents:
        if any(agent not in g for g in grids):
            continue
        slips = sum(_stat(g, agent, "macro_slip_events") for g in grids)
        rows.append(f"| {agent} | {_cell(default, agent)} | {slips:.0f} | {spread(agent, 'median_error')} | "
                    f"{spread(agent, 'median_error_slip_failed')} |")
    return "\n".join(rows + ["", targets_count(paths, learned)])


def heldout_overview(runs: dict[str, tuple[str, Path]] = HELDOUT_RUNS, learned: str = LEARNED) -> str | None:
    """One row per v2 held-out grid: the learned agent's median / P90 / macro-slips beside the best
    median, the best P90 and the fewest macro-slips of the agents that do not read the truth; None
    when a summary is missing."""
    rows = [f"| suite (episodes) | {learned} | best other median | best other P90 | fewest other macro-slips |",
            "|---|---|---|---|---|"]
    for label, out in runs.values():
        summary = _load(out / "summary.json", learned)
        if summary is None:
            return None
        med, p90, slips = (_best(summary, learned, k) for k in ("median_error", "p90_error", "macro_slip_events"))
        rows.append(f"| {label.removeprefix('v2 ')} ({summary[learned]['episodes']}) | {_cell(summary, learned)} | "
                    f"{med} {100 * _stat(summary, med, 'median_error'):.1f} % | {p90} {100 * _stat(summary, p90, 'p90_error'):.1f} % | "
                    f"{slips} {_stat(summary, slips, 'macro_slip_events'):.0f} |")
    return "\n".join(rows)



def heldout_shapes(runs: dict[str, tuple[str, Path]] = HELDOUT_RUNS, learned: str = LEARNED) -> str | None:
    """One row per creep-curve shape (a ``note`` group) of each v2 held-out grid: the learned agent's macro-slips
    and its median, beside the fewest macro-slips of the agents that do not read the truth there (ties: every
    agent that has them); None when a summary is missing."""
    rows = [f"| suite | shape or condition (episodes) | {learned}: macro-slips | {learned}: median | "
            "fewest other macro-slips |",
            "|---|---|---|---|---|"]
    for label, out in runs.values():
        summary = _load(out / "summary.json", learned)
        if summary is None:
            return None
        others = [a for a, v in summary.items() if not v["oracle"] and a != learned]
        for group, cell in summary[learned]["breakdown"].items():
            if not group.startswith("note "):
                continue
            slips = {a: summary[a]["breakdown"][group]["macro_slip_events"] for a in others}
            fewest = min(slips.values())
            rivals = ", ".join(a for a in others if slips[a] == fewest)
            rows.append(f"| {label.removeprefix('v2 ')} | {group.removeprefix('note ')} ({cell['episodes']}) | "
                        f"{cell['macro_slip_events']} | {100 * cell['median_error']:.1f} % | {rivals} {fewest} |")
    return "\n".join(rows)

HORIZON_AGENTS = ("phase-rule", "robust-model")  # the agents beside the learned one in the horizon table
LONGER_HORIZONS = (45, 60)  # the default suite's longer horizons (steps); each held-out grid's: the last
HORIZON_SUITES = {"default": ("v2 default suite", ROOT / "out" / "evaluate"),  # suite -> (label, its 30-step run)
                  **{name: (label, out) for name, (label, out) in zip(v2_heldout_grids(), HELDOUT_RUNS.values())}}


def with_horizon(suite: str, steps: int, root: Path = ROOT) -> Path:
    """Where ``cof-gym evaluate [--suite experiments/suites/SUITE.json] --env-kwargs max_windows:STEPS`` writes by default."""
    from cof_gym.commands.evaluate import default_out

    return root / default_out("default" if suite == "default" else f"experiments/suites/{suite}.json",
                              {"max_windows": steps})


def horizon(suites: dict[str, tuple[str, Path]] = HORIZON_SUITES, learned: str = LEARNED, root: Path = ROOT) -> str | None:
    """The learned agent and :data:`HORIZON_AGENTS` on each suite at the task's 30 steps and with longer horizons
    (:data:`LONGER_HORIZONS` for the default suite, the longest for the others): median / P90 / macro-slips, and
    the learned agent's episodes that ended at the horizon; None when a summary is missing."""
    rows = [f"| suite | steps | {learned}: median / P90 / macro-slips (episodes) | {learned} ended at the horizon | "
            + " | ".join(HORIZON_AGENTS) + " |", "|---" * (4 + len(HORIZON_AGENTS)) + "|"]
    for name, (label, out) in suites.items():
        longer = LONGER_HORIZONS if name == "default" else LONGER_HORIZONS[-1:]
        for steps, path in ((30, out), *((w, with_horizon(name, w, root)) for w in longer)):
            summary = _load(path / "summary.json", learned)
            if summary is None or any(a not in summary for a in HORIZON_AGENTS):
                return None
            ended = summary[learned]["breakdown"].get("ended: horizon", {}).get("episodes", 0)
            rows.append(f"| {label} | {steps} | {_cell(summary, learned)} ({summary[learned]['episodes']}) | {ended} | "
                        + " | ".join(_cell(summary, a) for a in HORIZON_AGENTS) + " |")
    return "\n".join(rows)


def _lowest(mine: float, best: float) -> str:
    return "yes" if mine < best else "tied" if mine == best else "no"


def slip_failed(paths: dict[str, Path] = TARGET_SUITES, learned: str = LEARNED) -> str | None:
    """Per suite of the targets: the learned agent's median and P90 error with a macro-slip counted as a failed
    measurement (100 %) beside the lowest of the agents that do not read the truth, and whether the learned
    agent's is lower (``tied`` where equal, e.g. two P90s at 100 %); None when a summary is missing or predates
    those metrics."""
    keys = ("median_error_slip_failed", "p90_error_slip_failed")
    rows = [f"| suite | {learned}: median / P90 (episodes) | lowest other median | lowest other P90 | "
            "lowest median | lowest P90 |", "|---|---|---|---|---|---|"]
    for label, path in paths.items():
        summary = _load(path, learned)
        if summary is None or any(k not in summary[learned] for k in keys):
            return None
        med, p90 = (100 * _stat(summary, learned, k) for k in keys)
        rivals = [_best(summary, learned, k) for k in keys]
        best = [100 * _stat(summary, rival, k) for rival, k in zip(rivals, keys)]
        rows.append(f"| {label} | {med:.1f} % / {p90:.1f} % ({summary[learned]['episodes']}) | {rivals[0]} {best[0]:.1f} % | "
                    f"{rivals[1]} {best[1]:.1f} % | {_lowest(med, best[0])} | {_lowest(p90, best[1])} |")
    return "\n".join(rows)


def _group(summary: dict, agent: str, group: str) -> dict:
    """The breakdown group ``group`` of ``agent`` in an evaluate summary (empty where the agent has no episode
    in it)."""
    return summary[agent]["breakdown"].get(group, {})


def horizon_ends(suites: dict[str, tuple[str, Path]] = HORIZON_SUITES, learned: str = LEARNED) -> str | None:
    """Per suite at the task's 30 steps: how many of the learned agent's episodes ended at the horizon, their mean
    peak torque (% of M_sat) and median / P90 error, beside the median of those it ended by its own stop (the
    breakdown's "ended" rows); None when a summary is missing."""
    rows = [f"| suite | {learned}: episodes | ended at the horizon | mean peak torque there [% of M_sat] | "
            "median / P90 there | median where it stopped |", "|---|---|---|---|---|---|"]
    for label, out in suites.values():
        summary = _load(out / "summary.json", learned)
        if summary is None:
            return None
        ended, stopped = _group(summary, learned, "ended: horizon"), _group(summary, learned, "ended: stop")
        there = (f"{100 * ended['peak_torque_fraction']:.1f} | {100 * ended['median_error']:.1f} % / "
                 f"{100 * ended['p90_error']:.1f} %") if ended else "- | -"
        rows.append(f"| {label} | {summary[learned]['episodes']} | {ended.get('episodes', 0)} | {there} | "
                    + (f"{100 * stopped['median_error']:.1f} % |" if stopped else "- |"))
    return "\n".join(rows)



def horizon_by_condition(suites: dict[str, tuple[str, Path]] = HORIZON_SUITES, learned: str = LEARNED) -> str | None:
    """Per suite and rail condition: the learned agent's episodes, how many ended at the horizon and their median
    error there (from each run's ``episodes.csv``); None when one is missing."""
    rows = [f"| suite | condition | {learned}: episodes | ended at the horizon | median there |",
            "|---|---|---|---|---|"]
    for label, out in suites.values():
        if not (out / "episodes.csv").is_file():
            return None
        with open(out / "episodes.csv", newline="") as f:
            mine = [r for r in csv.DictReader(f) if r["agent"] == learned]
        for condition in sorted({r["condition"] for r in mine}):
            group = [r for r in mine if r["condition"] == condition]
            ended = [abs(float(r["relative_error"])) for r in group if r["ended"] == "horizon"]
            there = f"{100 * float(np.median(ended)):.1f} %" if ended else "-"
            rows.append(f"| {label} | {condition} | {len(group)} | {len(ended)} | {there} |")
    return "\n".join(rows)

# the hand-built agents beside the learned one in the peak-creepage and edge-suite tables: the default list's agents
# that read no truth and ship no learned policy, in the registry's order (as `cof-gym evaluate` plays them)
HAND_BUILT_AGENTS = tuple(name for name in registry.default_agents()
                          if not registry.AGENTS[name].oracle and registry.AGENTS[name].shipped is None)


def peak_creepage(path: Path = TARGET_SUITES["v2 default suite (`cof-gym evaluate`)"], learned: str = LEARNED,
                  agents: tuple[str, ...] = HAND_BUILT_AGENTS) -> str | None:
    """The default suite's peak-creepage groups (the creepage of the true creep curve's peak): median / P90 /
    macro-slips of the learned agent and of ``agents`` in each; None when the summary is missing."""
    summary = _load(path, learned)
    if summary is None or any(a not in summary for a in agents):
        return None
    groups = [g for g in summary[learned]["breakdown"] if g.startswith("peak creepage")]
    rows = ["| peak creepage (episodes) | " + " | ".join((learned, *agents)) + " |", "|---" * (2 + len(agents)) + "|"]
    for group in groups:
        cells = [_triple(*(_group(summary, agent, group)[key] for key in ("median_error", "p90_error",
                                                                         "macro_slip_events")))
                 for agent in (learned, *agents)]
        rows.append(f"| {group.removeprefix('peak creepage ')} ({summary[learned]['breakdown'][group]['episodes']}) | "
                    + " | ".join(cells) + " |")
    return "\n".join(rows)


def heldout_peak_creepage(runs: dict[str, tuple[str, Path]] = HELDOUT_RUNS, learned: str = LEARNED,
                          agents: tuple[str, ...] = HAND_BUILT_AGENTS) -> str | None:
    """Where each agent runs away on the v2 held-out grids together: per peak-creepage group (the true creep curve's
    peak, the evaluator's ground truth), the episodes and each agent's macro-slips summed over the grids' summaries;
    None when a summary is missing."""
    summaries = [_load(out / "summary.json", learned) for _, out in runs.values()]
    if any(s is None or any(a not in s for a in agents) for s in summaries):
        return None
    present = {g for s in summaries for g in s[learned]["breakdown"]}
    groups = [g for g in (peak_creepage_band(lo) for lo in PEAK_CREEPAGE_BANDS[:-1]) if g in present]

    def total(agent: str, key: str, group: str | None) -> float:
        """``key`` of ``agent`` summed over the grids, in ``group`` (a grid without it: 0) or in all episodes."""
        if group is not None:
            return sum(_group(s, agent, group).get(key, 0) for s in summaries)
        return sum(s[agent]["episodes"] if key == "episodes" else _stat(s, agent, key) for s in summaries)

    rows = [f"| peak creepage (episodes) | {learned} | " + " | ".join(agents) + " |", "|---" * (2 + len(agents)) + "|"]
    for group in [*groups, None]:
        cells = [f"{total(agent, 'macro_slip_events', group):.0f}" for agent in (learned, *agents)]
        label = group.removeprefix("peak creepage ") if group else "all"
        rows.append(f"| {label} ({total(learned, 'episodes', group):.0f}) | " + " | ".join(cells) + " |")
    return "\n".join(rows)


EDGE_SUITES = {"v2 stress tables (`--suite experiments/suites/v2_stress_tables_grid.json`)":
               ROOT / "out" / "evaluate-v2-stress-tables" / "summary.json",
               "v2 extremes (`--suite experiments/suites/v2_extremes_grid.json`)":
               ROOT / "out" / "evaluate-v2-extremes" / "summary.json"}


def edge_suites(paths: dict[str, Path] = EDGE_SUITES, learned: str = LEARNED,
                agents: tuple[str, ...] = HAND_BUILT_AGENTS) -> str | None:
    """Per suite at the edges of what the env accepts: median / P90 / macro-slips of the learned agent and of
    ``agents``, the learned agent's mean peak torque and how often its calibrated interval holds the CoF; None when a
    summary is missing."""
    rows = [f"| suite (episodes) | {learned} | {learned}: mean peak torque [% of M_sat] | {learned}: CoF in its "
            "interval | " + " | ".join(agents) + " |", "|---" * (4 + len(agents)) + "|"]
    for label, path in paths.items():
        summary = _load(path, learned)
        if summary is None or any(a not in summary for a in agents):
            return None
        interval = summary[learned].get("interval", {}).get("coverage")
        rows.append(f"| {label} ({summary[learned]['episodes']}) | {_cell(summary, learned)} | "
                    f"{100 * _stat(summary, learned, 'peak_torque_fraction'):.1f} | "
                    + (f"{100 * interval['value']:.1f} %" if interval else "-") + " | "
                    + " | ".join(_cell(summary, a) for a in agents) + " |")
    return "\n".join(rows)


def paper_setting(path: Path = PAPER_RUN / "summary.json", learned: str = LEARNED) -> str | None:
    """The paper's setting (``cof-gym evaluate --suite paper``): every agent's median / P90 / macro-slips, how many of
    its episodes ended at the horizon, its mean peak torque (% of M_sat) and measurement time; None when the summary
    is missing."""
    summary = _load(path, learned)
    if summary is None:
        return None
    rows = ["| agent (episodes) | median / P90 / macro-slips | ended at the horizon | mean peak torque [% of M_sat] | "
            "measurement time [s] |", "|---|---|---|---|---|"]
    for agent, stats in summary.items():
        label = f"{agent} ({'oracle, ' if stats['oracle'] else ''}{stats['episodes']})"
        rows.append(f"| {label} | {_cell(summary, agent)} | "
                    f"{_group(summary, agent, 'ended: horizon').get('episodes', 0)} | "
                    f"{100 * _stat(summary, agent, 'peak_torque_fraction'):.1f} | "
                    f"{_stat(summary, agent, 'measurement_time_s'):.1f} |")
    return "\n".join(rows)


def validation_runs(prefix: str) -> dict[str, Path]:
    """The three validation grids' evaluate outputs ``out/PREFIX``, ``out/PREFIX-procedural``, ``-steep``."""
    return {grid: ROOT / "out" / (prefix + suffix)
            for grid, suffix in (("family", ""), ("procedural", "-procedural"), ("steep", "-steep"))}


SCRIPTED_AGENTS = ("staircase", "phase-rule", "model-based", "robust-model")  # the agents rules 24 and 29 judged
RUNAWAY_VALIDATION = validation_runs("runaway-validation")  # rule 24 (session 23): with and without +runaway
CEILING_VALIDATION = validation_runs("ceiling-validation")  # rule 29 (session 25): as registered and +ceiling


def variant_validation(runs: dict[str, Path], suffixes: tuple[str, str],
                       agents: tuple[str, ...] = SCRIPTED_AGENTS) -> str | None:
    """Median / P90 / macro-slips of each scripted agent under both name ``suffixes`` (``""``: as registered)
    on each validation grid (its cof-gym evaluate summary); None when a summary is missing."""
    summaries = {}
    for grid, out in runs.items():
        if not (out / "summary.json").is_file():
            return None
        summaries[grid] = json.loads((out / "summary.json").read_text())["summary"]
    episodes = {grid: summaries[grid][agents[0] + suffixes[0]]["episodes"] for grid in runs}
    rows = ["| agent | " + " | ".join(f"{grid} ({episodes[grid]}): median / P90 / macro-slips" for grid in runs) + " |",
            "|---" * (len(runs) + 1) + "|"]
    for agent in agents:
        for name in (agent + suffix for suffix in suffixes):
            rows.append(f"| {name} | " + " | ".join(_cell(summaries[grid], name) for grid in runs) + " |")
    return "\n".join(rows)


def runaway_validation(runs: dict[str, Path] = RUNAWAY_VALIDATION) -> str | None:
    """Rule 24's table: each scripted agent with and without ``+runaway``."""
    return variant_validation(runs, ("+plain", "+runaway"))


# rule 144 (session 88): the v3-fitted candidates (A: interrogator-v3, B: interrogator-v3-guarded) and the shipped
# interrogator on the validation grids played on v3, both vehicle configurations (selection data; the commands in the
# docstring write out/rule144-TAG-GRID-ctCONFIG)
RULE144_GRIDS = {"family": "v2_validation_grid", "procedural": "v2_validation_procedural_grid"}
RULE144_PLAYS = {label: [ROOT / "out" / f"rule144-{tag}-{grid}-ct{ct}" for tag in ("A", "B") for ct in (False, True)]
                 for label, grid in RULE144_GRIDS.items()}


def pooled_validation(plays: dict[str, list[Path]] = RULE144_PLAYS) -> str | None:
    """One row per agent of the plays ({grid: evaluate runs}; an agent's episodes pooled over a grid's runs): each
    grid's median / P90 / macro-slips, and over every grid the median and the P90 with a macro-slip (or an unscored
    episode) counted as 100 % error (``EpisodeRecord.error_slip_failed``, read back from episodes.csv's columns), as
    the recipe's selection ranks; None when a run is missing."""
    played: dict[str, dict[str, list[tuple[float, bool]]]] = {}
    for grid, runs in plays.items():
        for out in runs:
            if not (out / "episodes.csv").is_file():
                return None
            with open(out / "episodes.csv", newline="") as f:
                for r in csv.DictReader(f):
                    error = float(r["relative_error"]) if r["scored"] == "True" else 1.0
                    played.setdefault(r["agent"], {}).setdefault(grid, []).append((error, r["macro_slip"] == "True"))
    rows = ["| agent | " + " | ".join(f"{grid} grid: median / P90 / macro-slips (climbs)" for grid in plays)
            + " | pooled median, macro-slip = 100 % | pooled P90, macro-slip = 100 % |",
            "|---" * (len(plays) + 3) + "|"]
    for agent, grids in played.items():
        cells = []
        for grid in plays:
            errors = np.array([e for e, _ in grids[grid]])
            cells.append(f"{100 * np.median(errors):.1f} % / {100 * np.percentile(errors, 90):.1f} % / "
                         f"{sum(slip for _, slip in grids[grid])} ({errors.size})")
        failed = np.array([1.0 if slip else e for grid in plays for e, slip in grids[grid]])
        rows.append(f"| {agent} | {' | '.join(cells)} | {100 * np.median(failed):.1f} % | "
                    f"{100 * np.percentile(failed, 90):.1f} % |")
    return "\n".join(rows)


def ceiling_validation(runs: dict[str, Path] = CEILING_VALIDATION) -> str | None:
    """Rule 29's table: each scripted agent as registered and with ``+ceiling``."""
    return variant_validation(runs, ("", "+ceiling"))


GENERATED = {"targets": targets, "targets_count": targets_count, "paired_targets": paired_targets,
             "slip_rates": slip_rates,
             "at_a_glance": at_a_glance,
             "heldout_overview": heldout_overview, "heldout_shapes": heldout_shapes,
             "slip_failed": slip_failed, "horizon": horizon,
             "horizon_ends": horizon_ends, "horizon_by_condition": horizon_by_condition, "peak_creepage": peak_creepage,
             "heldout_peak_creepage": heldout_peak_creepage, "edge_suites": edge_suites,
             "paper_setting": paper_setting,
             "runaway_validation": runaway_validation, "ceiling_validation": ceiling_validation,
             "in_service_heldout_overview": lambda: heldout_overview(IN_SERVICE_HELDOUT_RUNS, V3_LEARNED),
             "rule144_validation": pooled_validation,
             "in_service_heldout_peak_creepage": lambda: heldout_peak_creepage(IN_SERVICE_HELDOUT_RUNS, V3_LEARNED,
                                                                               IN_SERVICE_RIVALS),
             }  # block -> its generator


def _shown(path: Path) -> str:
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def _block(name: str) -> re.Pattern:
    return re.compile(rf"(<!-- results:{name}:begin -->\n).*?(<!-- results:{name}:end -->)", re.S)


def fill(texts: dict[Path, str], name: str, content: str | None, source: str) -> None:
    """Put ``content`` into the block ``name`` of whichever document holds it (None: leave it as it is)."""
    holders = [doc for doc, text in texts.items() if _block(name).search(text)]
    if not holders:
        print(f"no document has a results:{name} block")
    elif content is None:
        print(f"results:{name} left as it is ({source} missing)")
    else:
        for doc in holders:
            texts[doc] = _block(name).sub(lambda m: m.group(1) + content + "\n" + m.group(2), texts[doc])
        print(f"{', '.join(_shown(d) for d in holders)}: results:{name} <- {source}")


def main(argv: list[str] | None = None) -> None:
    # no options: a parser so that --help (or a stray argument) explains and changes nothing
    Parser(prog="readme_results.py", description="Copy measured agent results into README.md, docs/results.md and "
           "docs/interrogator.md (run from the repository root after the commands in this script's docstring), so "
           "that their tables are generated, never typed.").parse_args(argv)
    for src, dst in FIGURES.items():
        if src.is_file():
            shutil.copyfile(src, dst)
            print(f"{dst.relative_to(ROOT)} <- {src.relative_to(ROOT)}")
        else:
            print(f"{src} missing: {dst.relative_to(ROOT)} left as it is")
    texts = {doc: doc.read_text() for doc in DOCUMENTS}
    for name, path in SOURCES.items():
        fill(texts, name, body(path) if path.is_file() else None, _shown(path))
    for name, generate in GENERATED.items():
        fill(texts, name, generate(), "the evaluate summaries (or the learned agent in one)")
    for doc, text in texts.items():
        doc.write_text(text)


if __name__ == "__main__":
    main()
